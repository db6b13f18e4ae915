"""The records of a config file's sections: pydantic models of shape and types, one per mapping.

Parameters and anchors (:class:`FreeRecord`, :class:`AnchorRecord`, ...), the routed spring, the
clearance, and the sections ``mechanism``, ``workspace``, ``solve``, ``scenarios``. Every record
is named ``<Name>Record`` in Python and ``<Name>`` in the JSON Schema (its ``title``, and the key
of its definition there: :data:`SCHEMA_NAMES`). Units are SI: lengths [m], forces [N], masses [kg],
angles [rad] (degrees where ``workspace.degrees`` says so), gravity [m/s²].
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Annotated, Any, Literal, Optional, Union, cast

import annotated_types
from pydantic import ConfigDict, Field

from springbalance.design.clearance import FIT_ROUNDS
from springbalance.io.schema.fields import (
    KIND_KEYS,
    Aggregate,
    Counting,
    Direction,
    Interval,
    NonNegative,
    Number,
    Positive,
    Record,
    Seed,
    Text,
    Vector2,
    Vector3,
    WorkspaceKind,
    at_most_one,
    by_shape,
    choice,
    exactly_one,
    expect,
    optional,
)
from springbalance.io.schema.solve_record import SolveRecord
from springbalance.model.mechanism import MAX_FLOOR


class FreeRecord(Record, title="Free"):
    """A design variable ``{lower, upper, init?}``: a number between the bounds, found by the solver."""

    lower: Number = Field(description="lower bound (in the parameter's unit)")
    upper: Number = Field(description="upper bound, ≥ lower")
    init: Number = optional("first start of the multi-start; default the middle of the bounds")


class NonNegativeFreeRecord(FreeRecord, title="NonNegativeFree"):
    """A design variable ``{lower ≥ 0, upper, init?}`` of a parameter that must be ≥ 0."""

    lower: NonNegative = Field(description="lower bound, ≥ 0 (in the parameter's unit)")


Parameter = by_shape(scalar=Annotated[Number, expect("a number or {lower, upper, init?}")], mapping=FreeRecord)
if TYPE_CHECKING:  # what by_shape builds at run time (a tagged union), as mypy can read it
    NonNegativeParameter = Union[float, NonNegativeFreeRecord]
else:
    NonNegativeParameter = by_shape(
        scalar=Annotated[NonNegative, expect("a number ≥ 0 or {lower, upper, init?}", bounds=False)],
        mapping=NonNegativeFreeRecord,
    )


class BoxRecord(Record, title="Box"):
    """An anchor point free in an axis-aligned box [m]; components with equal bounds stay fixed."""

    lower: Vector3 = Field(description="lower corner [m], body frame")
    upper: Vector3 = Field(description="upper corner [m], body frame")
    init: Vector3 = optional("first start [m]; default the middle of the box")


class SegmentRecord(Record, title="Segment"):
    """An anchor point free on a segment; the design variable is the fraction along it."""

    start: Vector3 = Field(description="start of the segment [m], body frame")
    end: Vector3 = Field(description="end of the segment [m], body frame")
    lower: Number = Field(0.0, description="lowest fraction along the segment [1]")
    upper: Number = Field(1.0, description="highest fraction along the segment [1]")
    init: Number = optional("first start (a fraction) [1]; default the middle")


class PlaneRecord(Record, title="Plane"):
    """An anchor point free in a rectangle ``origin + s·u + t·v`` (u, v normalised; bounds on s, t in m)."""

    origin: Vector3 = Field(description="origin of the rectangle's coordinates [m], body frame")
    u: Direction = Field(description="first direction (normalised)")
    v: Direction = Field(description="second direction (normalised), not parallel to u")
    lower: Vector2 = Field(description="lower bounds of (s, t) [m]")
    upper: Vector2 = Field(description="upper bounds of (s, t) [m]")
    init: Vector2 = optional("first start of (s, t) [m]; default the middle")


class MountPlaneRecord(Record, title="MountPlane"):
    """A mounting plane: a point on it and its normal, in the anchor body's frame (the world for universe)."""

    point: Vector3 = Field(description="a point of the plane [m]")
    normal: Direction = Field(description="the plane's normal")


class AnchorRecord(Record, title="Anchor"):
    """One end of a spring: a body and a point of it, fixed or free (at most one of point, box, segment, plane),
    optionally mounted on a surface (``on``)."""

    model_config = ConfigDict(json_schema_extra=at_most_one(("point", "box", "segment", "plane")))

    body: Text = Field(description="URDF link name, or universe (the world)")
    point: Vector3 = optional("a fixed point [m] in the body frame", shown=[0.0, 0.0, 0.0])
    box: BoxRecord = optional("free in an axis-aligned box [m]")
    segment: SegmentRecord = optional("free on a segment")
    plane: PlaneRecord = optional("free in a rectangle of a plane")
    on: Union[Literal["collision", "floor"], MountPlaneRecord] = optional(
        "mount the anchor on a surface: collision (the body's own collision surface, within the box or around "
        "the geometry), floor (the world plane z = 0, within the box) or a plane {point, normal} (within the box)"
    )
    offset: NonNegative = optional("with on: collision, the distance [m] out from the surface (a bracket)", shown=0.0)


class PulleySizeRecord(Record, title="PulleySize"):
    """A wrapping pulley (docs/model.md §3.9)."""

    radius: NonNegative = Field(0.0, description="radius [m]; 0 is a guide point the cable runs through")


class PathPointRecord(AnchorRecord, title="PathPoint"):
    """A point of a routed spring's path: a body and a point of it, fixed or free (as an anchor); the
    points between the ends may carry a pulley."""

    pulley: PulleySizeRecord = optional("a pulley at this point (points between the path's ends only)")


class RoutedSpringRecord(Record, title="RoutedSpring"):
    """A spring whose body lies on the path's first segment, pulling a cable over pulleys (or guide points)
    to the path's last point (docs/model.md §3.9)."""

    name: Text = optional("unique name; default s1, s2, ... by position")
    type: Literal["routed"] = Field(description="a routed spring")
    path: Annotated[
        list[PathPointRecord], annotated_types.MinLen(2), expect("a list of at least two points", deep=False)
    ] = Field(description="the spring's fixed end, then pulleys or guide points, then the cable's end")
    spring: dict[str, Any] = Field(
        description="the spring's law, a two-point spring record without ends: {type?, ideal?, stiffness, "
        "free_length, ...}; for a coil (type extension or compression without ideal: true) "
        "helical: {material, ...} gives its options"
    )
    cable_length: NonNegativeParameter = Field(
        description="length of the cable [m]: a number (fixed) or {lower, upper, init?} (a design variable)"
    )


class ClearanceRecord(Record, title="Clearance"):
    """How far the springs keep from the arm's links (docs/model.md §11)."""

    margin: NonNegative = Field(
        0.005, description="smallest distance [m] between a spring and a link it is not attached to, over the workspace"
    )
    check_samples: Counting = Field(
        1024, description="poses checked while fitting (a 4× denser set is checked at the end)"
    )
    radius: Positive = optional("capsule radius [m] of springs without a helical spec sheet (default 0.01)")
    between_springs: bool = Field(False, description="keep the springs the margin from each other too")
    buffer: NonNegative = optional(
        "extra distance [m] asked for between checked poses (default 10 % of the margin, at least 0.5 mm)"
    )
    rounds: Counting = Field(FIT_ROUNDS, description="most re-solves of the fitting loop")
    starts: Counting = Field(
        1,
        description="how many of the multi-start's best designs are fitted (each from its "
        "own start); the fitted design of lowest objective is kept",
    )


#: what a pseudo-base keeps of the world's orientation (springbalance.model.pseudo_bases.KEEPS)
if TYPE_CHECKING:
    Keep = Literal["orientation", "vertical"]
else:
    Keep = choice(("orientation", "vertical"), "keep")


class PseudoBaseRecord(Record, title="PseudoBase"):
    """A pseudo-base ``pb_<joint>`` at a joint's origin, keeping the world's orientation (docs/model.md §1.1)."""

    joint: Text = Field(description="the joint at whose origin the pseudo-base sits")
    mass: NonNegative = Field(0.0, description="mass [kg] of the pseudo-base and the parallelograms realising it")
    com: Vector3 = Field(
        [0.0, 0.0, 0.0], description="its centre of mass [m], world-aligned axes at the joint's origin"
    )
    keep: Keep = Field(
        "orientation",
        description="orientation: keep the world's orientation; vertical: keep only the world's z axis (turning "
        "with the arm's leading vertical-axis joints, fewer mimic joints)",
    )


if TYPE_CHECKING:
    _PseudoBase = Union[str, PseudoBaseRecord]
else:
    _PseudoBase = by_shape(scalar=Text, mapping=PseudoBaseRecord)


# ---------------------------------------------------------------------- sections
# the key `validate` shadows the deprecated classmethod BaseModel.validate, which nothing here calls
with warnings.catch_warnings():
    warnings.filterwarnings("ignore", message='Field name "validate"', category=UserWarning)

    class MechanismRecord(Record, title="Mechanism"):
        """The arm: a URDF file or an example-robot-data robot (exactly one of ``urdf`` and ``robot``), and gravity."""

        model_config = ConfigDict(json_schema_extra=exactly_one(("urdf", "robot")))

        urdf: Text = optional("URDF file of the arm, relative to the config file's folder")
        robot: Text = optional("example-robot-data robot name (ur5, panda, ...; see `springbalance robots`)")
        gravity: Annotated[
            Union[Number, Annotated[list[Number], annotated_types.Len(3, 3)]],
            expect("a magnitude [m/s²] or a 3-vector"),
        ] = optional(
            "magnitude g [m/s²], meaning (0, 0, -g), or the gravity vector [m/s²] in the world frame", shown=9.81
        )
        floor: Annotated[Number, annotated_types.Interval(ge=-MAX_FLOOR, le=MAX_FLOOR)] = optional(
            "height [m] of the floor or table the arm stands on, the world plane z = floor: with a clearance, the "
            "springs keep its margin above it (a spring anchored on the ground or the arm's base is exempt)"
        )
        mimic: bool = Field(False, description="parse URDF mimic joints as coupled joints (closed chains)")
        pseudo_bases: list[_PseudoBase] = optional(
            "joints that get a pseudo-base pb_<joint> (a joint name or {joint, mass, com}); see docs/model.md §1.1"
        )
        # pydantic lets a field shadow the deprecated classmethod BaseModel.validate; mypy sees a clash
        validate: bool = Field(  # type: ignore[assignment]
            True,
            description="check the arm's physics at load (masses ≥ 0, inertias positive semi-definite within "
            "the triangle inequality, joint limits lower ≤ upper); false loads a deliberately odd "
            "URDF anyway",
        )


class CouplingRecord(Record, title="Coupling"):
    """Keep only the samples with ``range[0] ≤ expression ≤ range[1]``."""

    expression: Text = Field(description='a linear combination of joint names, e.g. "elbow - shoulder"')
    range: Interval = Field(description="[lower, upper] of the expression [rad or m; degrees if workspace.degrees]")


if TYPE_CHECKING:  # what by_shape builds at run time (tagged unions), as mypy can read them
    _RangeValue = Union[list[float], float]
    _Count = Union[int, dict[str, int]]
    _Row = Union[list[float], float]
else:
    _RangeValue = by_shape(list=Interval, scalar=Annotated[Number, expect("[lower, upper] or a single value")])
    _Count = by_shape(scalar=Counting, mapping=dict[str, Counting])
    _Row = by_shape(list=list[Number], scalar=Number)


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
    rules.append({"if": is_kind("array"), "then": exactly_one(("values", "file"))})
    return {"allOf": rules}


class WorkspaceRecord(Record, title="Workspace"):
    """The finite set of poses over which a design is judged; ``{}`` samples 1024 Sobol points of the URDF limits."""

    model_config = ConfigDict(json_schema_extra=_workspace_rules())

    kind: WorkspaceKind = Field(
        default="sobol", description="grid, sobol (scrambled Sobol points), random, sweep (one joint moves) or array"
    )
    n: _Count = optional(
        "grid: points per joint, or {joint: count} (default 16); sobol, random: number of "
        "samples (default 1024); sweep: number of points, ≥ 2 (default 181)"
    )
    seed: Seed = Field(default=0, description="sobol, random: seed of the sequence")
    degrees: bool = Field(
        default=False, description="angles of revolute joints in ranges, couplings and values/file are in degrees"
    )
    ranges: Annotated[dict[str, _RangeValue], expect("a mapping joint name → [lower, upper]", deep=False)] = optional(
        "grid, sobol, random, sweep: {joint: [lower, upper]} [rad or m], or a single value that holds "
        "the joint; unlisted joints use their URDF limits"
    )
    couplings: Annotated[list[CouplingRecord], expect("a list of {expression, range} mappings", deep=False)] = optional(
        "grid, sobol, random: keep only the samples where each linear combination of joints lies in its range"
    )
    joint: Text = optional("sweep (required): the joint that moves; the others stay at the middle of their ranges")
    values: Annotated[list[_Row], annotated_types.MinLen(1), expect("a non-empty list of rows", deep=False)] = optional(
        "array: explicit samples, one row of nv joint values [rad or m] each, in the mechanism's joint order"
    )
    file: Text = optional(
        "array: samples from a .npy array (N×nv) or a .csv file (optional header of "
        "joint names), relative to the config file's folder"
    )
    ordered: bool = Field(
        default=True, description="array: the rows form a path (a trajectory), which the energy objective needs"
    )


class PayloadRecord(Record, title="Payload"):
    """A point mass carried by a body in one load case."""

    body: Text = Field(description="the body (URDF link) that carries it")
    mass: Number = Field(description="mass [kg]")
    point: Vector3 = optional("position [m] in the body frame", shown=[0.0, 0.0, 0.0])


if TYPE_CHECKING:  # what by_shape builds at run time (a tagged union), as mypy can read it
    _MassScale = Union[float, dict[str, float]]
else:
    _MassScale = by_shape(scalar=Number, mapping=dict[str, Number])


class LoadCaseRecord(Record, title="LoadCase"):
    """One scenario: payloads and a scale of the link masses."""

    name: Text = optional("name of the scenario; default 'case <number>'")
    payloads: Annotated[list[PayloadRecord], expect("a list of {body, mass, point?}", deep=False)] = optional(
        "point masses of this case", shown=[]
    )
    mass_scale: _MassScale = optional(
        "β [1] for every moving body, or {body: β} (a body's β also scales the links welded to it)"
    )


class PayloadRangeRecord(Record, title="PayloadRange"):
    """One scenario per mass of ``masses``, each a point mass at ``point`` of ``body``."""

    body: Text = Field(description="the body (URDF link) that carries the payload")
    point: Vector3 = optional("position [m] in the body frame", shown=[0.0, 0.0, 0.0])
    masses: Annotated[list[NonNegative], annotated_types.MinLen(1), expect("a non-empty list of masses ≥ 0 [kg]")] = (
        Field(description="payload masses [kg]")
    )


class ScenariosRecord(Record, title="Scenarios"):
    """Load cases over which one design is made: exactly one of ``cases`` and ``payload_range``."""

    model_config = ConfigDict(json_schema_extra=exactly_one(("cases", "payload_range")))

    cases: Annotated[
        list[LoadCaseRecord], annotated_types.MinLen(1), expect("a non-empty list of cases", deep=False)
    ] = optional("one scenario each")
    payload_range: PayloadRangeRecord = optional("one scenario per payload mass")
    per_scenario: Annotated[
        list[Annotated[str, annotated_types.MinLen(1)]], expect("a list of variable names (e.g. [s1.b])")
    ] = Field(
        default_factory=list,
        description="variables with one value per scenario: a spring end (s1.b) or a "
        "parameter (s1.initial_tension); the others are shared",
    )
    aggregate: Aggregate = Field(
        "sum",
        description="sum: the objective over the samples of all scenarios together; worst: the largest "
        "per-scenario value",
    )


Weights = Annotated[dict[str, NonNegative], expect("a mapping joint name → weight ≥ 0", deep=False)]
#: ``max_spring_mass``: a bound on the springs' total mass [kg]
MassBound = Annotated[Positive, expect("a number > 0 [kg]")]


class WorkspaceFileRecord(Record, title="WorkspaceFile"):
    """A file read for its ``workspace`` section only (the other sections may be there, unread)."""

    mechanism: Any = None
    workspace: Optional[WorkspaceRecord] = None
    springs: Any = None
    objective: Any = None
    weights: Any = None
    solve: Any = None
    scenarios: Any = None
    no_joint_worse: Any = None
    clearance: Any = None
    max_spring_mass: Any = None


#: every record class of this module, by its name in the JSON Schema (its name before it was ``<Name>Record``).
RECORDS: dict[str, type[Record]] = {
    cast(str, cls.model_config["title"]): cls
    for cls in (  # every record has a title
        FreeRecord,
        NonNegativeFreeRecord,
        BoxRecord,
        SegmentRecord,
        PlaneRecord,
        MountPlaneRecord,
        AnchorRecord,
        PulleySizeRecord,
        PathPointRecord,
        RoutedSpringRecord,
        ClearanceRecord,
        MechanismRecord,
        CouplingRecord,
        WorkspaceRecord,
        SolveRecord,
        PayloadRecord,
        LoadCaseRecord,
        PayloadRangeRecord,
        ScenariosRecord,
        WorkspaceFileRecord,
    )
}
#: the name in the JSON Schema of each record class (a definition's key, as its title).
SCHEMA_NAMES: dict[str, str] = {cls.__name__: name for name, cls in RECORDS.items()}
