"""The building blocks of the config records: the :class:`Record` base, the field helpers, the value types.

A :class:`Record` rejects unknown keys (naming the valid ones), takes types strictly and numbers
only when finite. The helpers give every failure a one-line message: :func:`expect` (``expected
<what>, got <value>``), :func:`choice` (``unknown <what> 'x'; valid: ...``), :func:`by_shape` (a
union whose branch is chosen by the value's shape, so that the error is that of the branch meant)
and :func:`optional` (a key that may be absent). Units: lengths [m], forces [N], angles [rad].
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Annotated, Any, Literal, Union

import annotated_types
import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict, Discriminator, Field, Tag, WrapValidator
from pydantic_core import PydanticCustomError

from springbalance.design.objectives import OBJECTIVES
from springbalance.design.problem import AGGREGATES
from springbalance.design.solvers import METHODS
from springbalance.design.verification_loop import MODES as VERIFY_MODES

#: top-level sections of a config file, and those it must have.
SECTIONS = (
    "mechanism",
    "workspace",
    "springs",
    "objective",
    "weights",
    "solve",
    "scenarios",
    "no_joint_worse",
    "clearance",
    "max_spring_mass",
    "tolerance",
)
REQUIRED_SECTIONS = ("mechanism", "workspace", "springs")
WORKSPACE_KINDS = ("grid", "sobol", "random", "sweep", "array")
#: which workspace keys apply to which kind (``kind`` and ``degrees`` apply to all).
KIND_KEYS = {
    "grid": ("n", "ranges", "couplings"),
    "sobol": ("n", "seed", "ranges", "couplings"),
    "random": ("n", "seed", "ranges", "couplings"),
    "sweep": ("n", "ranges", "joint"),
    "array": ("values", "file", "ordered"),
}
#: the law of a spring record without ``type``.
DEFAULT_SPRING_TYPE = "extension"


# ---------------------------------------------------------------------- building blocks
#: pydantic's error types of a value of the wrong type, and what the value should have been.
EXPECTED_TYPES = {
    "float_type": "a number",
    "int_type": "an integer",
    "int_from_float": "an integer",
    "bool_type": "true or false",
    "string_type": "a string",
    "list_type": "a list",
    "dict_type": "a mapping",
    "model_type": "a mapping",
    "model_attributes_type": "a mapping",
    "expected_mapping": "a mapping",
}


def fail(kind: str, message: str, key: str | None = None) -> PydanticCustomError:
    """A validation error whose message is ``message``; ``key`` extends the key path of the error."""
    return PydanticCustomError(kind, "{message}", {"message": message, **({"config_key": key} if key else {})})


def abbreviated(value: object, limit: int = 200) -> str:
    """``repr(value)``, cut to ``limit`` characters."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def expect(what: str, deep: bool = True, bounds: bool = True) -> WrapValidator:
    """On failure say ``expected <what>, got <value>``: for every error of the value (``deep``) or
    only for those of the value itself (its type, its length), letting errors inside it through;
    without ``bounds``, a value of the right type out of its bounds keeps its own message."""

    def validate(value: Any, handler: Callable[[Any], Any]) -> Any:
        try:
            return handler(value)
        except pydantic.ValidationError as error:
            details = error.errors()
            if (deep or all(not detail["loc"] for detail in details)) and (
                bounds or any(detail["type"] in EXPECTED_TYPES for detail in details)
            ):
                raise fail("expected", f"expected {what}, got {abbreviated(value)}") from None
            raise

    return WrapValidator(validate)


def choice(values: Iterable[str], what: str) -> Any:
    """One of ``values`` (a JSON Schema enum); otherwise ``unknown <what> 'x'; valid: a, b``."""
    values = tuple(values)

    def validate(value: Any, handler: Callable[[Any], Any]) -> Any:
        try:
            return handler(value)
        except pydantic.ValidationError:
            raise fail("unknown_choice", f"unknown {what} {abbreviated(value)}; valid: {', '.join(values)}") from None

    return Annotated[Literal[values], WrapValidator(validate)]


def _integral(value: Any) -> Any:
    """``3.0`` (also written ``3e0``) counts as the integer 3."""
    return int(value) if isinstance(value, float) and value.is_integer() else value


def integer_at_least(minimum: int) -> Any:
    """An integer ≥ ``minimum``; a float of integral value (``3.0``) counts."""
    return Annotated[int, annotated_types.Ge(minimum), BeforeValidator(_integral)]


def by_shape(**branches: Any) -> Any:
    """A union of ``mapping``, ``list`` and ``scalar`` branches, chosen by the value's shape, so that
    an error is reported for the branch that was meant."""
    members = tuple(Annotated[branch, Tag(shape)] for shape, branch in branches.items())

    def shape(value: Any) -> str:
        if isinstance(value, (dict, BaseModel)) and "mapping" in branches:
            return "mapping"
        if isinstance(value, list) and "list" in branches:
            return "list"
        return "scalar" if "scalar" in branches else next(iter(branches))

    return Annotated[Union[members], Discriminator(shape)]


def _no_default(schema: dict) -> None:
    schema.pop("default", None)


def optional(description: str, shown: Any = None, **kwargs: Any) -> Any:
    """An optional key: absent is ``None`` in the model, and ``null`` is not a valid value. The JSON
    Schema shows ``shown`` as its default (the value the key takes when absent), if given."""
    extra = _no_default if shown is None else (lambda schema: schema.update(default=shown))
    return Field(None, description=description, json_schema_extra=extra, **kwargs)


Number = float  # finite (Record.model_config), an int is taken too
NonNegative = Annotated[float, annotated_types.Ge(0)]
Positive = Annotated[float, annotated_types.Gt(0)]
Text = Annotated[str, annotated_types.MinLen(1), expect("a non-empty string")]
Vector3 = Annotated[list[Number], annotated_types.Len(3, 3), expect("three numbers [m]")]
Direction = Annotated[list[Number], annotated_types.Len(3, 3), expect("three numbers")]
Vector2 = Annotated[list[Number], annotated_types.Len(2, 2), expect("two numbers [m]")]
Interval = Annotated[list[Number], annotated_types.Len(2, 2), expect("[lower, upper] (numbers)")]
Counting = integer_at_least(1)  # an integer ≥ 1 (a count)
Seed = integer_at_least(0)  # an integer ≥ 0
NonNegativeCount = integer_at_least(0)  # an integer ≥ 0: a budget that may be none
WorkspaceKind = choice(WORKSPACE_KINDS, "workspace kind")
Objective = choice(OBJECTIVES, "objective")
Method = choice(METHODS, "method")
VerifyMode = choice(VERIFY_MODES, "verify mode")
Aggregate = choice(AGGREGATES, "aggregate")


class Record(BaseModel):
    """Base of every record of a config: strict types, finite numbers, unknown keys rejected.

    An unknown key is reported at the record, with the list of its valid keys.
    """

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)

    @pydantic.model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        if isinstance(data, cls):
            return data
        valid = list(cls.model_fields)
        if not isinstance(data, dict):
            raise fail("expected_mapping", f"expected a mapping with keys {', '.join(valid)}, got {abbreviated(data)}")
        unknown = [key for key in data if key not in valid]
        if unknown:
            raise fail("unknown_key", f"unknown key {unknown[0]!r}; valid keys: {', '.join(valid)}")
        cls._check_record(data)
        return data

    @classmethod
    def _check_record(cls, data: dict) -> None:
        """Further checks of the raw mapping, after its keys (for subclasses)."""


def at_most_one(keys: Sequence[str]) -> dict:
    """JSON Schema: no two of ``keys`` together."""
    return {"not": {"anyOf": [{"required": [a, b]} for i, a in enumerate(keys) for b in keys[i + 1 :]]}}


def exactly_one(keys: Sequence[str]) -> dict:
    """JSON Schema: exactly one of ``keys``."""
    return {"oneOf": [{"required": [key]} for key in keys]}
