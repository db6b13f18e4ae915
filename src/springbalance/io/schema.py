"""The config file's schema: pydantic models of every section, its JSON Schema, and one-line errors.

Each section of a config file is a :class:`Record` (a pydantic model that rejects unknown keys,
takes types strictly and numbers only when finite). The spring records are built from the law
registry :data:`springbalance.springs.SPRING_TYPES`: every law class says its ``kind``, its
``ends``, its ``parameter_units`` (with ``defaults`` and ``nonnegative``) and its
``option_types`` / ``required_options``, and :func:`spring_model` turns that into a model, so a
new law module appears here (and in the JSON Schema) without an edit to this package.

The models check shape and types only. What needs the URDF (bodies and joints that exist),
orders between values (lower ≤ upper) and the rules between keys (one of ``urdf``/``robot``,
keys that apply to a workspace kind) are checked by :mod:`springbalance.io.config` after them.
:func:`validated` turns a :class:`pydantic.ValidationError` into the one-line
:class:`~springbalance.errors.ConfigError` ``<file>: <key path>: <what>`` of the rest of the
config code.

Units are SI (m, N, N/m, rad, kg, m/s²) unless ``workspace.degrees`` is true (then angles of
revolute joints in the workspace section are in degrees).
"""

import functools
import importlib
import inspect
import json
import re
import types
import typing
import warnings
from typing import Annotated, Any, Literal, Optional, Union

import annotated_types
import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict, Discriminator, Field, Tag, WrapValidator
from pydantic.json_schema import GenerateJsonSchema
from pydantic_core import PydanticCustomError

from springbalance.design.objectives import OBJECTIVES
from springbalance.design.problem import AGGREGATES
from springbalance.design.solvers import METHODS
from springbalance.errors import ConfigError
from springbalance.springs import SPRING_TYPES
from springbalance.springs.records import ROUTED, ideal_law_hint

JSON_SCHEMA_DIALECT = "https://json-schema.org/draft/2020-12/schema"
TITLE = "springbalance config"

#: top-level sections of a config file, and those it must have.
SECTIONS = ("mechanism", "workspace", "springs", "objective", "weights", "solve", "scenarios", "no_joint_worse",
            "clearance")
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
def _fail(kind: str, message: str, key: str | None = None) -> PydanticCustomError:
    """A validation error whose message is ``message``; ``key`` extends the key path of the error."""
    return PydanticCustomError(kind, "{message}", {"message": message, **({"config_key": key} if key else {})})


def _shown(value, limit: int = 200) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _expect(what: str, deep: bool = True, bounds: bool = True) -> WrapValidator:
    """On failure say ``expected <what>, got <value>``: for every error of the value (``deep``) or
    only for those of the value itself (its type, its length), letting errors inside it through;
    without ``bounds``, a value of the right type out of its bounds keeps its own message."""

    def validate(value, handler):
        try:
            return handler(value)
        except pydantic.ValidationError as error:
            details = error.errors()
            if (deep or all(not detail["loc"] for detail in details)) and (
                    bounds or any(detail["type"] in _EXPECTED for detail in details)):
                raise _fail("expected", f"expected {what}, got {_shown(value)}") from None
            raise

    return WrapValidator(validate)


def _choice(values, what: str):
    """One of ``values`` (a JSON Schema enum); otherwise ``unknown <what> 'x'; valid: a, b``."""
    values = tuple(values)

    def validate(value, handler):
        try:
            return handler(value)
        except pydantic.ValidationError:
            raise _fail("unknown_choice", f"unknown {what} {_shown(value)}; valid: {', '.join(values)}") from None

    return Annotated[Literal[values], WrapValidator(validate)]


def _integral(value):
    """``3.0`` (also written ``3e0``) counts as the integer 3."""
    return int(value) if isinstance(value, float) and value.is_integer() else value


def _integer(minimum: int):
    return Annotated[int, annotated_types.Ge(minimum), BeforeValidator(_integral)]


def _by_shape(**branches):
    """A union of ``mapping``, ``list`` and ``scalar`` branches, chosen by the value's shape, so that
    an error is reported for the branch that was meant."""
    members = tuple(Annotated[branch, Tag(shape)] for shape, branch in branches.items())

    def shape(value) -> str:
        if isinstance(value, (dict, BaseModel)) and "mapping" in branches:
            return "mapping"
        if isinstance(value, list) and "list" in branches:
            return "list"
        return "scalar" if "scalar" in branches else next(iter(branches))

    return Annotated[Union[members], Discriminator(shape)]


def _no_default(schema: dict) -> None:
    schema.pop("default", None)


def _optional(description: str, shown=None, **kwargs):
    """An optional key: absent is ``None`` in the model, and ``null`` is not a valid value. The JSON
    Schema shows ``shown`` as its default (the value the key takes when absent), if given."""
    extra = _no_default if shown is None else (lambda schema: schema.update(default=shown))
    return Field(None, description=description, json_schema_extra=extra, **kwargs)


Number = float  # finite (Record.model_config), an int is taken too
NonNegative = Annotated[float, annotated_types.Ge(0)]
Positive = Annotated[float, annotated_types.Gt(0)]
Text = Annotated[str, annotated_types.MinLen(1), _expect("a non-empty string")]
Vector3 = Annotated[list[Number], annotated_types.Len(3, 3), _expect("three numbers [m]")]
Direction = Annotated[list[Number], annotated_types.Len(3, 3), _expect("three numbers")]
Vector2 = Annotated[list[Number], annotated_types.Len(2, 2), _expect("two numbers [m]")]
Interval = Annotated[list[Number], annotated_types.Len(2, 2), _expect("[lower, upper] (numbers)")]
Counting = _integer(1)   # an integer ≥ 1 (a count)
Seed = _integer(0)       # an integer ≥ 0
WorkspaceKind = _choice(WORKSPACE_KINDS, "workspace kind")
Objective = _choice(OBJECTIVES, "objective")
Method = _choice(METHODS, "method")
Aggregate = _choice(AGGREGATES, "aggregate")


class Record(BaseModel):
    """Base of every record of a config: strict types, finite numbers, unknown keys rejected.

    An unknown key is reported at the record, with the list of its valid keys.
    """

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)

    @pydantic.model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data):
        if isinstance(data, cls):
            return data
        valid = list(cls.model_fields)
        if not isinstance(data, dict):
            raise _fail("expected_mapping", f"expected a mapping with keys {', '.join(valid)}, got {_shown(data)}")
        unknown = [key for key in data if key not in valid]
        if unknown:
            raise _fail("unknown_key", f"unknown key {unknown[0]!r}; valid keys: {', '.join(valid)}")
        cls._check_record(data)
        return data

    @classmethod
    def _check_record(cls, data: dict) -> None:
        """Further checks of the raw mapping, after its keys (for subclasses)."""


def _at_most_one(keys) -> dict:
    """JSON Schema: no two of ``keys`` together."""
    return {"not": {"anyOf": [{"required": [a, b]} for i, a in enumerate(keys) for b in keys[i + 1:]]}}


def _exactly_one(keys) -> dict:
    return {"oneOf": [{"required": [key]} for key in keys]}


# ---------------------------------------------------------------------- parameters and anchors
class Free(Record):
    """A design variable ``{lower, upper, init?}``: a number between the bounds, found by the solver."""

    lower: Number = Field(description="lower bound (in the parameter's unit)")
    upper: Number = Field(description="upper bound, ≥ lower")
    init: Number = _optional("first start of the multi-start; default the middle of the bounds")


class NonNegativeFree(Free):
    """A design variable ``{lower ≥ 0, upper, init?}`` of a parameter that must be ≥ 0."""

    lower: NonNegative = Field(description="lower bound, ≥ 0 (in the parameter's unit)")


Parameter = _by_shape(scalar=Annotated[Number, _expect("a number or {lower, upper, init?}")], mapping=Free)
NonNegativeParameter = _by_shape(
    scalar=Annotated[NonNegative, _expect("a number ≥ 0 or {lower, upper, init?}", bounds=False)],
    mapping=NonNegativeFree)


class Box(Record):
    """An anchor point free in an axis-aligned box [m]; components with equal bounds stay fixed."""

    lower: Vector3 = Field(description="lower corner [m], body frame")
    upper: Vector3 = Field(description="upper corner [m], body frame")
    init: Vector3 = _optional("first start [m]; default the middle of the box")


class Segment(Record):
    """An anchor point free on a segment; the design variable is the fraction along it."""

    start: Vector3 = Field(description="start of the segment [m], body frame")
    end: Vector3 = Field(description="end of the segment [m], body frame")
    lower: Number = Field(0.0, description="lowest fraction along the segment [1]")
    upper: Number = Field(1.0, description="highest fraction along the segment [1]")
    init: Number = _optional("first start (a fraction) [1]; default the middle")


class Plane(Record):
    """An anchor point free in a rectangle ``origin + s·u + t·v`` (u, v normalised; bounds on s, t in m)."""

    origin: Vector3 = Field(description="origin of the rectangle's coordinates [m], body frame")
    u: Direction = Field(description="first direction (normalised)")
    v: Direction = Field(description="second direction (normalised), not parallel to u")
    lower: Vector2 = Field(description="lower bounds of (s, t) [m]")
    upper: Vector2 = Field(description="upper bounds of (s, t) [m]")
    init: Vector2 = _optional("first start of (s, t) [m]; default the middle")


class MountPlane(Record):
    """A mounting plane: a point on it and its normal, in the anchor body's frame (the world for universe)."""

    point: Vector3 = Field(description="a point of the plane [m]")
    normal: Direction = Field(description="the plane's normal")


class Anchor(Record):
    """One end of a spring: a body and a point of it, fixed or free (at most one of point, box, segment, plane),
    optionally mounted on a surface (``on``)."""

    model_config = ConfigDict(json_schema_extra=_at_most_one(("point", "box", "segment", "plane")))

    body: Text = Field(description="URDF link name, or universe (the world)")
    point: Vector3 = _optional("a fixed point [m] in the body frame", shown=[0.0, 0.0, 0.0])
    box: Box = _optional("free in an axis-aligned box [m]")
    segment: Segment = _optional("free on a segment")
    plane: Plane = _optional("free in a rectangle of a plane")
    on: Union[Literal["collision", "floor"], MountPlane] = _optional(
        "mount the anchor on a surface: collision (the body's own collision surface, within the box or around "
        "the geometry), floor (the world plane z = 0, within the box) or a plane {point, normal} (within the box)")
    offset: NonNegative = _optional("with on: collision, the distance [m] out from the surface (a bracket)",
                                    shown=0.0)


class PulleySize(Record):
    """A wrapping pulley (docs/model.md §3.9)."""

    radius: NonNegative = Field(0.0, description="radius [m]; 0 is a guide point the cable runs through")


class PathPoint(Anchor):
    """A point of a routed spring's path: a body and a point of it, fixed or free (as an anchor); the
    points between the ends may carry a pulley."""

    pulley: PulleySize = _optional("a pulley at this point (points between the path's ends only)")


class RoutedSpring(Record):
    """A spring whose body lies on the path's first segment, pulling a cable over pulleys (or guide points)
    to the path's last point (docs/model.md §3.9)."""

    name: Text = _optional("unique name; default s1, s2, ... by position")
    type: Literal["routed"] = Field(description="a routed spring")
    path: Annotated[list[PathPoint], annotated_types.MinLen(2), _expect("a list of at least two points", deep=False)] = Field(
        description="the spring's fixed end, then pulleys or guide points, then the cable's end")
    spring: dict[str, Any] = Field(
        description="the spring's law, a two-point spring record without ends: {type?, ideal?, stiffness, "
                    "free_length, ...}; for a coil (type extension or compression without ideal: true) "
                    "helical: {material, ...} gives its options")
    cable_length: NonNegativeParameter = Field(description="length of the cable [m]: a number (fixed) or "
                                                           "{lower, upper, init?} (a design variable)")


class Clearance(Record):
    """How far the springs keep from the arm's links (docs/model.md §11)."""

    margin: NonNegative = Field(0.005, description="smallest distance [m] between a spring and a link it is not "
                                                   "attached to, over the workspace")
    check_samples: Counting = Field(1024, description="poses checked while fitting (a 4× denser set is "
                                                         "checked at the end)")
    radius: Positive = _optional("capsule radius [m] of springs without a helical spec sheet (default 0.01)")
    between_springs: bool = Field(False, description="keep the springs the margin from each other too")
    buffer: NonNegative = _optional("extra distance [m] asked for between checked poses (default 10 % of the "
                                    "margin, at least 0.5 mm)")
    rounds: Counting = Field(12, description="most re-solves of the fitting loop")
    starts: Counting = Field(1, description="how many of the multi-start's best designs are fitted (each from its "
                                            "own start); the fitted design of lowest objective is kept")


# ---------------------------------------------------------------------- springs, from the registry
_PARAMETER_TEXT = {
    "stiffness": "rate k", "free_length": "free length l0", "initial_tension": "initial tension F0",
    "preload": "preload", "force": "force F0 (positive pulls, negative pushes)", "neutral_angle": "neutral angle q0",
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


def _docstring_args(cls) -> dict[str, str]:
    """``name: text`` entries of the ``Args:`` sections (Google style) of ``cls`` and its bases."""
    found: dict[str, str] = {}
    for klass in reversed(cls.__mro__):
        section, entry_indent, names = None, None, []
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


def _summary(cls) -> str:
    """The first paragraph of the class docstring, on one line."""
    paragraph = inspect.cleandoc(cls.__doc__ or "").split("\n\n")[0]
    return _plain(paragraph).rstrip(":;,.") + "."


def _plain(text: str) -> str:
    """Docstring text on one line, without reST roles and with single backquotes."""
    text = re.sub(r":\w+:`~?(?:[\w.]+\.)?(\w+)`", r"\1", text)    # cross-references: the name
    text = re.sub(r":\w+:`([^`]*)`", r"`\1`", text).replace("``", "`")  # math and the like: as code
    return " ".join(text.split())


def _init_default(cls, key: str):
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


def _adopted(annotation):
    """``annotation`` with every pydantic model in it (outside :class:`Record`) adopted, and every
    forward reference to one (``ForwardRef(name, module=...)``, as the spring laws name the
    records of :mod:`springbalance.springs.options`) resolved."""
    if isinstance(annotation, typing.ForwardRef) and annotation.__forward_module__ is not None:
        annotation = getattr(importlib.import_module(annotation.__forward_module__), annotation.__forward_arg__)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel) and not issubclass(annotation, Record):
        return _adopted_model(annotation)
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is Annotated:
        return Annotated[(_adopted(args[0]), *args[1:])]
    if origin in (Union, types.UnionType):
        return Union[tuple(_adopted(arg) for arg in args)]
    if origin is list:
        return list[_adopted(args[0])]
    if origin is dict:
        return dict[args[0], _adopted(args[1])]
    return annotation


def _option_text(cls, key: str, args: dict[str, str]) -> str:
    described = getattr(cls, "option_descriptions", {}) or {}
    return described.get(key) or _plain(args.get(key, "")) or _OPTION_TEXT.get(key) or f"option of the {cls.kind} law"


@functools.cache
def spring_model(cls) -> type[Record]:
    """The record model of spring law ``cls`` (a class of the registry), built from its class attributes:
    ``name``, ``type``, its ends (anchors ``a``/``b`` or a ``joint``), its parameters (a number or
    ``{lower, upper, init?}`` each, in the unit of ``parameter_units``) and its options."""
    args = _docstring_args(cls)
    default_kind = cls.kind == DEFAULT_SPRING_TYPE
    fields: dict[str, Any] = {
        "name": (str, _optional("unique name; design variables are <name>.<end>.<coordinate> and "
                                "<name>.<parameter>; default s1, s2, ... by position")),
        "type": (Literal[cls.kind], Field(cls.kind if default_kind else ...,
                                          description=f"the spring law{' (the default)' if default_kind else ''}")),
    }
    for end in cls.ends:
        if end == "joint":
            fields[end] = (Text, Field(description="the joint it acts on (a revolute or continuous joint)"))
        else:
            fields[end] = (Anchor, Field(description=f"end {end}: {{body, point | box | segment | plane}}"))
    for key, unit in cls.parameter_units.items():
        nonnegative = key in cls.nonnegative
        description = (f"{_PARAMETER_TEXT.get(key, key)} [{unit}]: a number (fixed) or {{lower, upper, init?}} "
                       f"(a design variable){'; ≥ 0' if nonnegative else ''}")
        if key in args:
            description += f". {_plain(args[key])}"
        default = cls.defaults.get(key, ...)
        fields[key] = (NonNegativeParameter if nonnegative else Parameter, Field(default, description=description))
    for key, annotation in cls.option_types.items():
        text = _option_text(cls, key, args)
        if key in cls.required_options:
            field = Field(description=text)
        else:
            default = _init_default(cls, key)
            field = Field(default, description=text) if default is not None else _optional(text)
        fields[key] = (_adopted(annotation), field)
    return pydantic.create_model(cls.__name__, __base__=Record, __doc__=_summary(cls), __module__=__name__,
                                 **fields)


def _spring_tag(value):
    """The registry key of a record: its ``type``, with ``:ideal`` for ``ideal: true``."""
    if isinstance(value, dict):
        kind, ideal = value.get("type", DEFAULT_SPRING_TYPE), value.get("ideal", False)
    else:
        kind, ideal = getattr(value, "type", None), getattr(value, "ideal", False)
    return f"{kind}:ideal" if ideal is True else kind


def _spring_union(laws: tuple):
    """One spring record: the model of the law its ``type`` names (default ``extension``)."""
    keys = tuple(key for key, _ in laws)
    kinds = tuple(dict.fromkeys(cls.kind for _, cls in laws)) + (ROUTED,)

    def check(value):
        if not isinstance(value, dict):
            raise _fail("expected_mapping", f"expected a mapping (a spring record), got {_shown(value)}")
        kind = value.get("type", DEFAULT_SPRING_TYPE)
        if not isinstance(kind, str) or kind not in kinds:
            raise _fail("unknown_spring_type", f"unknown spring type {_shown(kind)}; valid: {', '.join(kinds)}",
                        key="type")
        if kind == ROUTED:
            return value
        ideal = value.get("ideal", False)
        if not isinstance(ideal, bool):
            raise _fail("expected", f"expected true or false, got {_shown(ideal)}", key="ideal")
        if ideal and f"{kind}:ideal" not in keys:
            variants = ", ".join(key.split(":")[0] for key in keys if key.endswith(":ideal"))
            raise _fail("no_ideal_variant", f"a {kind!r} spring has no ideal variant (only {variants} do)", key="ideal")
        hint = ideal_law_hint(dict(laws)[f"{kind}:ideal" if ideal else kind], value)
        if hint:
            raise _fail("ideal_law_key", hint)
        return value

    members = tuple(Annotated[spring_model(cls), Tag(kind)] for kind, cls in laws) + (
        Annotated[RoutedSpring, Tag(ROUTED)],)
    return Annotated[Annotated[Union[members], Discriminator(_spring_tag)], BeforeValidator(check)]


def spring_list(laws: tuple | None = None):
    """The type of the ``springs`` section: a non-empty list of spring records."""
    laws = tuple(SPRING_TYPES.items()) if laws is None else laws
    return Annotated[list[_spring_union(laws)], annotated_types.MinLen(1),
                     _expect("a non-empty list of springs", deep=False)]


def spring_list_adapter() -> pydantic.TypeAdapter:
    """A validator of a ``springs`` list on its own."""
    return _spring_list_adapter(tuple(SPRING_TYPES.items()))


@functools.cache
def _spring_list_adapter(laws: tuple) -> pydantic.TypeAdapter:
    return pydantic.TypeAdapter(spring_list(laws))


# ---------------------------------------------------------------------- sections
# the key `validate` shadows the deprecated classmethod BaseModel.validate, which nothing here calls
with warnings.catch_warnings():
    warnings.filterwarnings("ignore", message='Field name "validate"', category=UserWarning)

    class Mechanism(Record):
        """The arm: a URDF file or an example-robot-data robot (exactly one of ``urdf`` and ``robot``), and gravity."""

        model_config = ConfigDict(json_schema_extra=_exactly_one(("urdf", "robot")))

        urdf: Text = _optional("URDF file of the arm, relative to the config file's folder")
        robot: Text = _optional("example-robot-data robot name (ur5, panda, ...; see `springbalance robots`)")
        gravity: Annotated[Union[Number, Annotated[list[Number], annotated_types.Len(3, 3)]],
                           _expect("a magnitude [m/s²] or a 3-vector")] = _optional(
            "magnitude g [m/s²], meaning (0, 0, -g), or the gravity vector [m/s²] in the world frame", shown=9.81)
        mimic: bool = Field(False, description="parse URDF mimic joints as coupled joints (closed chains)")
        validate: bool = Field(True, description="check the arm's physics at load (masses ≥ 0, inertias positive "
                                                 "semi-definite within the triangle inequality, joint limits lower ≤ "
                                                 "upper); false loads a deliberately odd URDF anyway")


class Coupling(Record):
    """Keep only the samples with ``range[0] ≤ expression ≤ range[1]``."""

    expression: Text = Field(description='a linear combination of joint names, e.g. "elbow - shoulder"')
    range: Interval = Field(description="[lower, upper] of the expression [rad or m; degrees if workspace.degrees]")


_RangeValue = _by_shape(list=Interval, scalar=Annotated[Number, _expect("[lower, upper] or a single value")])
_Count = _by_shape(scalar=Counting, mapping=dict[str, Counting])
_Row = _by_shape(list=list[Number], scalar=Number)


def _workspace_rules() -> dict:
    """JSON Schema: the keys of each kind (a kind-less workspace is sobol), sweep needs its joint,
    array exactly one of values and file."""
    rules = []
    for key in dict.fromkeys(key for keys in KIND_KEYS.values() for key in keys):
        users = [kind for kind, keys in KIND_KEYS.items() if key in keys]
        then = {"properties": {"kind": {"enum": users}}, **({} if "sobol" in users else {"required": ["kind"]})}
        rules.append({"if": {"required": [key]}, "then": then})
    is_kind = lambda kind: {"properties": {"kind": {"const": kind}}, "required": ["kind"]}  # noqa: E731
    rules.append({"if": is_kind("sweep"), "then": {"required": ["joint"]}})
    rules.append({"if": is_kind("array"), "then": _exactly_one(("values", "file"))})
    return {"allOf": rules}


class Workspace(Record):
    """The finite set of poses over which a design is judged; ``{}`` samples 1024 Sobol points of the URDF limits."""

    model_config = ConfigDict(json_schema_extra=_workspace_rules())

    kind: WorkspaceKind = Field(
        "sobol", description="grid, sobol (scrambled Sobol points), random, sweep (one joint moves) or array")
    n: _Count = _optional("grid: points per joint, or {joint: count} (default 16); sobol, random: number of "
                          "samples (default 1024); sweep: number of points, ≥ 2 (default 181)")
    seed: Seed = Field(0, description="sobol, random: seed of the sequence")
    degrees: bool = Field(False, description="angles of revolute joints in ranges, couplings and values/file "
                                             "are in degrees")
    ranges: Annotated[dict[str, _RangeValue], _expect("a mapping joint name → [lower, upper]", deep=False)] = \
        _optional("grid, sobol, random, sweep: {joint: [lower, upper]} [rad or m], or a single value that holds "
                  "the joint; unlisted joints use their URDF limits")
    couplings: Annotated[list[Coupling], _expect("a list of {expression, range} mappings", deep=False)] = \
        _optional("grid, sobol, random: keep only the samples where each linear combination of joints lies "
                  "in its range")
    joint: Text = _optional("sweep (required): the joint that moves; the others stay at the middle of "
                            "their ranges")
    values: Annotated[list[_Row], annotated_types.MinLen(1), _expect("a non-empty list of rows", deep=False)] = \
        _optional("array: explicit samples, one row of nv joint values [rad or m] each, in the mechanism's "
                  "joint order")
    file: Text = _optional("array: samples from a .npy array (N×nv) or a .csv file (optional header of "
                           "joint names), relative to the config file's folder")
    ordered: bool = Field(True, description="array: the rows form a path (a trajectory), which the energy "
                                            "objective needs")


class Solve(Record):
    """Options of the multi-start solve (the command line's --starts, --seed, --method, --workers override them)."""

    starts: Counting = _optional("starts of the multi-start: the initial guess, then scrambled Sobol "
                                    "points of the bounds", shown=8)
    seed: Seed = _optional("seed of the start points; results are deterministic given it", shown=0)
    method: Method = _optional(
        "least_squares (bounded Gauss-Newton, for rms and pe_variance), ipopt (general NLP) or auto", shown="auto")
    max_iterations: Counting = _optional("iteration budget of each start (and of each IPOPT phase)", shown=100)
    tolerance: Positive = _optional("least squares stop when a step lowers the cost by less than this "
                                    "fraction [1]; IPOPT uses min(tolerance, 1e-8)", shown=1e-8)
    workers: Counting = _optional("processes that run the starts at once (the design does not depend on it); "
                                  "default $SPRINGBALANCE_WORKERS, else the number of cores, once a start "
                                  "lasts long enough to pay for the pool")


class Payload(Record):
    """A point mass carried by a body in one load case."""

    body: Text = Field(description="the body (URDF link) that carries it")
    mass: Number = Field(description="mass [kg]")
    point: Vector3 = _optional("position [m] in the body frame", shown=[0.0, 0.0, 0.0])


_MassScale = _by_shape(scalar=Number, mapping=dict[str, Number])


class LoadCase(Record):
    """One scenario: payloads and a scale of the link masses."""

    name: Text = _optional("name of the scenario; default 'case <number>'")
    payloads: Annotated[list[Payload], _expect("a list of {body, mass, point?}", deep=False)] = _optional(
        "point masses of this case", shown=[])
    mass_scale: _MassScale = _optional(
        "β [1] for every moving body, or {body: β} (a body's β also scales the links welded to it)")


class PayloadRange(Record):
    """One scenario per mass of ``masses``, each a point mass at ``point`` of ``body``."""

    body: Text = Field(description="the body (URDF link) that carries the payload")
    point: Vector3 = _optional("position [m] in the body frame", shown=[0.0, 0.0, 0.0])
    masses: Annotated[list[NonNegative], annotated_types.MinLen(1),
                      _expect("a non-empty list of masses ≥ 0 [kg]")] = Field(description="payload masses [kg]")


class Scenarios(Record):
    """Load cases over which one design is made: exactly one of ``cases`` and ``payload_range``."""

    model_config = ConfigDict(json_schema_extra=_exactly_one(("cases", "payload_range")))

    cases: Annotated[list[LoadCase], annotated_types.MinLen(1), _expect("a non-empty list of cases", deep=False)] = \
        _optional("one scenario each")
    payload_range: PayloadRange = _optional("one scenario per payload mass")
    per_scenario: Annotated[list[Annotated[str, annotated_types.MinLen(1)]],
                            _expect("a list of variable names (e.g. [s1.b])")] = Field(
        default_factory=list, description="variables with one value per scenario: a spring end (s1.b) or a "
                                          "parameter (s1.initial_tension); the others are shared")
    aggregate: Aggregate = Field(
        "sum", description="sum: the objective over the samples of all scenarios together; worst: the largest "
                           "per-scenario value")


Weights = Annotated[dict[str, NonNegative], _expect("a mapping joint name → weight ≥ 0", deep=False)]


class _ConfigRecord(Record):
    """A springbalance config: the arm, its workspace, the springs to design, and how to design them.

    Units are SI (m, N, N/m, rad, kg, m/s²); with workspace.degrees, angles of revolute joints in the
    workspace section are in degrees. Relative paths are relative to the config file's folder."""

    model_config = ConfigDict(title=TITLE, json_schema_extra={"description": " ".join(
        "A springbalance config: the arm, its workspace, the springs to design, and how to design them. Units are SI "
        "(m, N, N/m, rad, kg, m/s²); with workspace.degrees, angles of revolute joints in the workspace section are "
        "in degrees. Relative paths are relative to the config file's folder.".split())})

    @classmethod
    def _check_record(cls, data: dict) -> None:
        for section in REQUIRED_SECTIONS:
            if section not in data:
                raise _fail("missing_section",
                            f"missing section {section!r} (required: {', '.join(REQUIRED_SECTIONS)})")


def config_model() -> type[Record]:
    """The model of a whole config file (rebuilt when a spring law registers itself)."""
    return _config_model(tuple(SPRING_TYPES.items()))


@functools.cache
def _config_model(laws: tuple) -> type[Record]:
    return pydantic.create_model(
        "Config", __base__=_ConfigRecord, __doc__=_ConfigRecord.__doc__, __module__=__name__,
        mechanism=(Mechanism, Field(description="the arm (required)")),
        workspace=(Optional[Workspace], Field(description="the poses over which a design is judged (required; "
                                                          "empty means 1024 Sobol points of the URDF limits)")),
        springs=(spring_list(laws), Field(description="the springs to design (required): one record each, "
                                                      "the format in which designs are saved")),
        objective=(Objective, Field("rms", description="rms, peak, pe_variance, energy (needs an ordered "
                                                       "workspace), joint_peaks (sum of the per-joint peaks) or "
                                                       "peak_then_joints (the worst joint first, then the others)")),
        weights=(Optional[Weights], Field(None, description="{joint: w ≥ 0}: joint weights of the objective; "
                                                            "default 1 for every joint")),
        solve=(Optional[Solve], Field(None, description="solver options")),
        scenarios=(Optional[Scenarios], Field(None, description="load cases (payloads, mass scales)")),
        no_joint_worse=(bool, Field(False, description="constrain every joint with a weight > 0 to stay at or "
                                                       "below its unbalanced peak torque at every sample")),
        clearance=(Optional[Clearance], Field(None, description="keep every spring this far from the arm's "
                                                                "collision geometry")),
    )


class WorkspaceFile(Record):
    """A file read for its ``workspace`` section only (the other sections may be there, unread)."""

    mechanism: Any = None
    workspace: Optional[Workspace] = None
    springs: Any = None
    objective: Any = None
    weights: Any = None
    solve: Any = None
    scenarios: Any = None
    no_joint_worse: Any = None
    clearance: Any = None


# ---------------------------------------------------------------------- JSON Schema
class _SchemaGenerator(GenerateJsonSchema):
    """Pydantic's JSON Schema without a title on every property (the descriptions say it all)."""

    def field_title_should_be_set(self, schema) -> bool:
        return False


def json_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a config file, for editors and other validators."""
    schema = config_model().model_json_schema(schema_generator=_SchemaGenerator)
    first = ("title", "description", "type", "properties", "required", "additionalProperties")
    ordered = {key: schema[key] for key in first if key in schema}
    rest = {key: value for key, value in schema.items() if key not in ordered and key != "$defs"}
    return {"$schema": JSON_SCHEMA_DIALECT, **ordered, **rest, "$defs": schema.get("$defs", {})}


def schema_text() -> str:
    """:func:`json_schema` as indented JSON text (what ``springbalance schema`` prints)."""
    return json.dumps(json_schema(), indent=2, ensure_ascii=False) + "\n"


# ---------------------------------------------------------------------- errors
_EXPECTED = {"float_type": "a number", "int_type": "an integer", "int_from_float": "an integer",
             "bool_type": "true or false", "string_type": "a string", "list_type": "a list",
             "dict_type": "a mapping", "model_type": "a mapping", "model_attributes_type": "a mapping",
             "expected_mapping": "a mapping"}
_BOUNDS = {"greater_than": ("gt", ">"), "greater_than_equal": ("ge", "≥"), "less_than": ("lt", "<"),
           "less_than_equal": ("le", "≤")}


def validated(model, data, where: str, top: bool = False, springs_at: tuple = ("springs",)):
    """``data`` validated by ``model`` (a pydantic model class or a :class:`pydantic.TypeAdapter`).

    Raises:
        ConfigError: ``<where>: <key path>: <what>`` for the first problem; ``top`` when ``where``
            is a file label (a colon before the key path) rather than a key path. ``springs_at`` is the
            key path of the spring list within ``data``: the key paths of spring errors name the spring.
    """
    validate = getattr(model, "model_validate", None) or model.validate_python
    try:
        return validate(data)
    except pydantic.ValidationError as error:
        raise ConfigError(describe(error, data, where, top, springs_at)) from None


def describe(error: pydantic.ValidationError, data, where: str, top: bool = False,
             springs_at: tuple = ("springs",)) -> str:
    """The one-line message of the most telling error of ``error`` (see :func:`validated`)."""
    found = [(detail, _steps(detail, data)) for detail in error.errors(include_url=False)]
    # a wrong type next to other errors of the same value is a branch of a union that was not meant
    meant = [(detail, steps) for detail, steps in found
             if not (detail["type"] in _EXPECTED and any(other is not detail and other_steps[:len(steps)] == steps
                                                         for other, other_steps in found))]
    detail, steps = (meant or found)[0]
    if not meant and detail["type"] in _EXPECTED:  # only wrong types: list what each branch takes
        options = list(dict.fromkeys(_EXPECTED[other["type"]] for other, other_steps in found
                                     if other_steps == steps and other["type"] in _EXPECTED))
        what = f"expected {' or '.join(options)}, got {_shown(detail['input'])}"
    elif detail["type"] == "missing":
        steps, what = steps[:-1], f"missing key {steps[-1][0]!r}"
    else:
        what = _what(detail)
    key = (detail.get("ctx") or {}).get("config_key")
    if key:
        steps = [*steps, (key, False)]
    path = _path(steps, data, springs_at)
    if top:
        prefix = f"{where}: {path}" if path else where
    else:
        prefix = where + ("" if not path or path.startswith("[") else ".") + path
    return f"{prefix}: {what}"


def _what(detail) -> str:
    kind, value, context = detail["type"], detail["input"], detail.get("ctx") or {}
    if "message" in context:
        return context["message"]
    if kind in _EXPECTED:
        return f"expected {_EXPECTED[kind]}, got {_shown(value)}"
    if kind in _BOUNDS:
        name, sign = _BOUNDS[kind]
        bound = context[name]
        bound = int(bound) if isinstance(bound, float) and bound.is_integer() else bound
        return f"must be {sign} {bound}, got {_shown(value)}"
    if kind == "finite_number":
        return f"{value!r} is not allowed; every number must be finite"
    if kind in ("too_short", "too_long"):
        length = context.get("min_length" if kind == "too_short" else "max_length")
        return f"expected {'at least' if kind == 'too_short' else 'at most'} {length} items, got {_shown(value)}"
    if kind == "literal_error":
        return f"unknown value {_shown(value)}; valid: {context.get('expected')}"
    if kind == "extra_forbidden":
        return "unknown key"
    message = detail["msg"]
    return f"{message[:1].lower()}{message[1:]}, got {_shown(value)}"


def _steps(detail, data) -> list[tuple[object, bool]]:
    """The key path of an error in ``data``: ``(key, is_list_index)`` steps. Parts of pydantic's
    location that are not keys of the data (union tags) are left out."""
    loc, steps, node = detail["loc"], [], data
    for position, part in enumerate(loc):
        if isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node):
            steps.append((part, True))
            node = node[part]
        elif isinstance(node, dict) and part in node:
            steps.append((part, False))
            node = node[part]
        elif detail["type"] == "missing" and position == len(loc) - 1:
            steps.append((part, False))
    return steps


def _path(steps, data, springs_at: tuple) -> str:
    """``springs[0] 'shoulder'.b.box``: keys joined by dots, list indices in brackets; a spring's
    name follows its index (unless the error is about its type or name)."""
    text, node = "", data
    for position, (part, index) in enumerate(steps):
        text += f"[{part}]" if index else (f".{part}" if text else str(part))
        node = node[part] if isinstance(node, (dict, list)) and (index or part in node) else None
        spring = (index and position == len(springs_at) and tuple(key for key, _ in steps[:position]) == springs_at)
        following = steps[position + 1][0] if position + 1 < len(steps) else None
        if spring and isinstance(node, dict) and following not in ("type", "name"):
            name = node.get("name")
            if isinstance(name, str) and name:
                text += f" {name!r}"
    return text
