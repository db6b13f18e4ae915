"""The records of the springs, built from the law registry :data:`springbalance.springs.SPRING_TYPES`.

Every law class says its ``kind``, its ``ends``, its ``parameter_units`` (with ``defaults`` and
``nonnegative``) and its ``option_types`` / ``required_options``, and :func:`spring_model` turns that
into a record, so a new law module appears in the config schema (and in the JSON Schema) without
an edit to this package. A parameter is a number (fixed) or ``{lower, upper, init?}`` (a design
variable) in the law's unit ([N/m], [m], [N], [N·m/rad], ...).
"""

from __future__ import annotations

import functools
import inspect
import re
import sys
import types
import typing
from typing import Annotated, Any, Literal, Union

import annotated_types
import pydantic
from pydantic import BaseModel, BeforeValidator, Discriminator, Field, Tag

import springbalance.springs.options  # noqa: F401  (the option records the laws name by forward references)
from springbalance.io.schema.fields import DEFAULT_SPRING_TYPE, Record, Text, abbreviated, expect, fail, optional
from springbalance.io.schema.records import AnchorRecord, NonNegativeParameter, Parameter, RoutedSpringRecord
from springbalance.springs import SPRING_TYPES, Spring
from springbalance.springs.records import ROUTED, ideal_law_hint

_PARAMETER_TEXT = {
    "stiffness": "rate k",
    "free_length": "free length l0",
    "initial_tension": "initial tension F0",
    "preload": "preload",
    "force": "force F0 (positive pulls, negative pushes)",
    "neutral_angle": "neutral angle q0",
}
_OPTION_TEXT = {
    "max_force": "|F| ≤ max_force [N] at every sample",
    "max_length": "L ≤ max_length [m] at every sample",
    "min_length": "L ≥ min_length [m] at every sample",
    "mass": "the spring's own mass: a number [kg] (fixed) or a coil mapping whose mass follows the stiffness",
    "keep_tension": "the spring never goes slack: L ≥ l0 at every sample",
    "max_stretch": "L ≤ max_stretch · l0 at every sample (a ratio > 1; catalogue springs: about 1.5)",
    "helical": "a helical spring of this material and index must exist for the design",
    "stays_compressed": "the spring stays in contact: L ≤ l0 at every sample",
    "stroke": "L ≥ l0 - stroke [m]: it cannot be compressed further",
    "max_torque": "|τ| ≤ max_torque [N·m] at every sample",
    "max_deflection": "|q - q0| ≤ max_deflection [rad] at every sample",
}


def _docstring_args(cls: type) -> dict[str, str]:
    """``name: text`` entries of the ``Args:`` sections (Google style) of ``cls`` and its bases."""
    found: dict[str, str] = {}
    for klass in reversed(cls.__mro__):
        section: int | None = None
        entry_indent: int | None = None
        names: list[str] = []
        for line in inspect.cleandoc(klass.__doc__ or "").splitlines():
            text, indent = line.strip(), len(line) - len(line.lstrip())
            if text in ("Args:", "Arguments:"):
                section, entry_indent, names = indent, None, []
            elif section is None or not text:
                continue
            elif indent <= section:
                section = None
            elif (entry_indent is None or indent == entry_indent) and re.match(r"^[\w, ]+:", text):
                entry_indent = indent
                head, _, rest = text.partition(":")
                names = [name.strip() for name in head.split(",")]
                found.update({name: rest.strip() for name in names})
            else:
                found.update({name: f"{found[name]} {text}" for name in names})
    return found


def _summary(cls: type) -> str:
    """The first paragraph of the class docstring, on one line."""
    paragraph = inspect.cleandoc(cls.__doc__ or "").split("\n\n")[0]
    return _plain(paragraph).rstrip(":;,.") + "."


def _plain(text: str) -> str:
    """Docstring text on one line, without reST roles and with single backquotes."""
    text = re.sub(r":\w+:`~?(?:[\w.]+\.)?(\w+)`", r"\1", text)  # cross-references: the name
    text = re.sub(r":\w+:`([^`]*)`", r"`\1`", text).replace("``", "`")  # math and the like: as code
    return " ".join(text.split())


def _init_default(cls: type, key: str) -> bool | int | float | str | None:
    """The default of keyword ``key`` in the ``__init__`` of ``cls`` or its bases, if a plain value (else None)."""
    for klass in cls.__mro__:
        init = klass.__dict__.get("__init__")
        if init is None:
            continue
        parameter = inspect.signature(init).parameters.get(key)
        if parameter is not None and parameter.default is not inspect.Parameter.empty:
            default = parameter.default
            return default if isinstance(default, (bool, int, float, str)) else None
    return None


@functools.cache
def _adopted_model(model: type[BaseModel]) -> type[BaseModel]:
    """``model`` (a pydantic record of an option) as a :class:`Record`: strict, with the same
    keys, so that its unknown keys are reported with the valid ones like every other record."""
    namespace = {"__doc__": model.__doc__, "__module__": model.__module__, "__qualname__": model.__qualname__}
    return types.new_class(model.__name__, (Record, model), exec_body=lambda ns: ns.update(namespace))


def _adopted(annotation: Any) -> Any:
    """``annotation`` with every pydantic model in it (outside :class:`Record`) adopted, and every
    forward reference to one (``ForwardRef(name, module=...)``, as the spring laws name the
    records of :mod:`springbalance.springs.options`) resolved."""
    if isinstance(annotation, typing.ForwardRef) and annotation.__forward_module__ is not None:
        module = sys.modules.get(annotation.__forward_module__)
        if module is None:
            raise ImportError(
                f"the option record {annotation.__forward_arg__!r} of a spring law is in module "
                f"{annotation.__forward_module__!r}, which is not imported"
            )
        annotation = getattr(module, annotation.__forward_arg__)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel) and not issubclass(annotation, Record):
        return _adopted_model(annotation)
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    # the annotation is rebuilt at run time from values, which mypy cannot read as types (hence the ignores)
    if origin is Annotated:
        parts = (_adopted(args[0]), *args[1:])
        return Annotated[parts]
    if origin in (Union, types.UnionType):
        return Union[tuple(_adopted(arg) for arg in args)]
    if origin is list:
        return list[_adopted(args[0])]  # type: ignore[misc]
    if origin is dict:
        return dict[args[0], _adopted(args[1])]  # type: ignore[misc, valid-type]
    return annotation


def _option_text(cls: type[Spring], key: str, args: dict[str, str]) -> str:
    described = getattr(cls, "option_descriptions", {}) or {}
    return described.get(key) or _plain(args.get(key, "")) or _OPTION_TEXT.get(key) or f"option of the {cls.kind} law"


@functools.cache
def spring_model(cls: type[Spring]) -> type[Record]:
    """The record model of spring law ``cls`` (a class of the registry), built from its class attributes:
    ``name``, ``type``, its ends (anchors ``a``/``b`` or a ``joint``), its parameters (a number or
    ``{lower, upper, init?}`` each, in the unit of ``parameter_units``) and its options."""
    args = _docstring_args(cls)
    default_kind = cls.kind == DEFAULT_SPRING_TYPE
    fields: dict[str, Any] = {
        "name": (
            str,
            optional(
                "unique name; design variables are <name>.<end>.<coordinate> and "
                "<name>.<parameter>; default s1, s2, ... by position"
            ),
        ),
        "type": (
            Literal[cls.kind],
            Field(
                cls.kind if default_kind else ...,
                description=f"the spring law{' (the default)' if default_kind else ''}",
            ),
        ),
    }
    for end in cls.ends:
        if end == "joint":
            fields[end] = (Text, Field(description="the joint it acts on (a revolute or continuous joint)"))
        else:
            fields[end] = (AnchorRecord, Field(description=f"end {end}: {{body, point | box | segment | plane}}"))
    for key, unit in cls.parameter_units.items():
        nonnegative = key in cls.nonnegative
        description = (
            f"{_PARAMETER_TEXT.get(key, key)} [{unit}]: a number (fixed) or {{lower, upper, init?}} "
            f"(a design variable){'; ≥ 0' if nonnegative else ''}"
        )
        if key in args:
            description += f". {_plain(args[key])}"
        default = cls.defaults.get(key, ...)
        fields[key] = (NonNegativeParameter if nonnegative else Parameter, Field(default, description=description))
    for key, annotation in cls.option_types.items():
        text = _option_text(cls, key, args)
        if key in cls.required_options:
            field = Field(description=text)
        else:
            init_default = _init_default(cls, key)
            field = Field(init_default, description=text) if init_default is not None else optional(text)
        fields[key] = (_adopted(annotation), field)
    return pydantic.create_model(cls.__name__, __base__=Record, __doc__=_summary(cls), __module__=__name__, **fields)


def _spring_tag(value: Any) -> str | None:
    """The registry key of a record: its ``type``, with ``:ideal`` for ``ideal: true``."""
    if isinstance(value, dict):
        kind, ideal = value.get("type", DEFAULT_SPRING_TYPE), value.get("ideal", False)
    else:
        kind, ideal = getattr(value, "type", None), getattr(value, "ideal", False)
    return f"{kind}:ideal" if ideal is True else kind


def _spring_union(laws: tuple) -> Any:
    """One spring record: the model of the law its ``type`` names (default ``extension``)."""
    keys = tuple(key for key, _ in laws)
    kinds = tuple(dict.fromkeys(cls.kind for _, cls in laws)) + (ROUTED,)

    def check(value: Any) -> Any:
        if not isinstance(value, dict):
            raise fail("expected_mapping", f"expected a mapping (a spring record), got {abbreviated(value)}")
        kind = value.get("type", DEFAULT_SPRING_TYPE)
        if not isinstance(kind, str) or kind not in kinds:
            raise fail(
                "unknown_spring_type", f"unknown spring type {abbreviated(kind)}; valid: {', '.join(kinds)}", key="type"
            )
        if kind == ROUTED:
            return value
        ideal = value.get("ideal", False)
        if not isinstance(ideal, bool):
            raise fail("expected", f"expected true or false, got {abbreviated(ideal)}", key="ideal")
        if ideal and f"{kind}:ideal" not in keys:
            variants = ", ".join(key.split(":")[0] for key in keys if key.endswith(":ideal"))
            raise fail("no_ideal_variant", f"a {kind!r} spring has no ideal variant (only {variants} do)", key="ideal")
        law = dict(laws)[f"{kind}:ideal" if ideal else kind]
        hint = ideal_law_hint(law, value)
        if hint:
            raise fail("ideal_law_key", hint)
        known = {"name", "type", "ideal", *law.ends, *law.parameter_units, *law.option_types}
        missing = [key for key in law.parameter_units if key not in law.defaults and key not in value]
        if missing and known.issuperset(value):  # (a misspelt key is the error to report: the record's own)
            key = missing[0]
            raise fail(
                "missing_parameter",
                f"missing key {key!r}: the {kind} spring's {_PARAMETER_TEXT.get(key, key)} "
                f"[{law.parameter_units[key]}], a number (fixed) or {{lower, upper}} (a design variable)",
            )
        return value

    members = tuple(Annotated[spring_model(cls), Tag(kind)] for kind, cls in laws) + (
        Annotated[RoutedSpringRecord, Tag(ROUTED)],
    )
    return Annotated[Annotated[Union[members], Discriminator(_spring_tag)], BeforeValidator(check)]


def spring_list(laws: tuple | None = None) -> Any:
    """The type of the ``springs`` section: a non-empty list of spring records."""
    laws = tuple(SPRING_TYPES.items()) if laws is None else laws
    return Annotated[
        list[_spring_union(laws)],  # type: ignore[misc]  # built at run time
        annotated_types.MinLen(1),
        expect("a non-empty list of springs", deep=False),
    ]


def spring_list_adapter() -> pydantic.TypeAdapter:
    """A validator of a ``springs`` list on its own."""
    return _spring_list_adapter(tuple(SPRING_TYPES.items()))


@functools.cache
def _spring_list_adapter(laws: tuple) -> pydantic.TypeAdapter:
    return pydantic.TypeAdapter(spring_list(laws))
