r"""The base class of every spring element, :class:`Spring`, and the registry of laws (docs/model.md §2–§5).

Every spring is an *element* that adds its share to the holding torque [N·m or N] and the
potential [J] at each workspace sample (:meth:`Spring.contribution`): two-point springs
(:class:`~springbalance.springs.laws.two_point.TwoPointSpring`) join a point of body A to a point
of body B; joint springs (such as :class:`~springbalance.springs.laws.torsional.TorsionalSpring`)
act on one joint coordinate.

A law is one module of this folder with one class: it sets ``kind`` (its ``type`` in configs and
saved designs), its parameters and options, and its force and potential, and it registers itself
in :data:`SPRING_TYPES` by subclassing. Laws are written with plain arithmetic, so one
implementation serves CasADi symbols (inside the optimiser) and NumPy arrays (checks, reports).
``parameters`` maps each parameter name to its value. Every parameter is a number or
:class:`~springbalance.springs.params.Free`. Each element reports one *state* and one
*generalised force* per sample: length [m] and tension [N] for two-point springs, joint angle
[rad] and torque [N·m] for torsional ones.
"""

from __future__ import annotations

import abc
import dataclasses
from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Protocol

import annotated_types
import numpy as np

from springbalance.errors import InputError
from springbalance.springs.params import Anchor, Free
from springbalance.springs.values import Parameters, Value

if TYPE_CHECKING:
    from springbalance.model.mechanism import Mechanism


class Sample(Protocol):
    """The per-sample state a law's :meth:`Spring.contribution` reads (built by
    :class:`~springbalance.design.torque_model.TorqueModel`)."""

    gravity: Any  #: the gravity vector [m/s²]

    def point(self, body: str, point: Any) -> Any:
        """World position [m] of a point of ``body`` (body frame, [m]) and its ``J_p^T f`` product."""

    def coordinate(self, joint: str) -> Any:
        """The joint's coordinate [rad or m]."""

    def direction(self, joint: str) -> Any:
        """The unit torque vector ``e_i`` of the joint (nv)."""

    def zero(self) -> Any:
        """An nv zero vector."""


#: spring ``type`` name in configs and saved designs -> class. Every subclass of :class:`Spring`
#: that sets ``kind`` adds itself; :mod:`springbalance.springs.laws` imports every law module.
SPRING_TYPES: dict[str, type[Spring]] = {}

#: option types of the config schema: a finite number > 0, a ratio > 1.
PositiveNumber = Annotated[float, annotated_types.Gt(0)]
StretchRatio = Annotated[float, annotated_types.Gt(1)]


@dataclasses.dataclass
class Contribution:
    """What one spring adds at one sample (CasADi expressions).

    Attributes:
        torque: its share of the holding torque ``∂V_s/∂q`` (nv) [N·m or N].
        potential: its potential energy [J] (elastic, plus the gravity of its own mass).
        state: length ``L`` [m] (two-point springs) or joint angle ``q_i`` [rad] (torsional).
        force: ``dV_s/d(state)``: tension [N] or torque [N·m].
    """

    torque: object
    potential: object
    state: object
    force: object
    #: what a constraint may need besides: ``segment`` [m], the length of a routed spring's first segment
    extra: dict = dataclasses.field(default_factory=dict)


class Spring(abc.ABC):
    """Base class of every spring element. Subclasses set ``kind``, ``parameter_units`` and the law.

    The per-sample ``sample`` object handed to :meth:`contribution` is built by
    :class:`~springbalance.design.torque_model.TorqueModel`; it gives ``sample.point(body, p)`` (world
    position of a body-fixed point and its ``J_p^T f`` product), ``sample.coordinate(joint)``
    (the joint's coordinate), ``sample.direction(joint)`` (the unit torque vector ``e_i``),
    ``sample.zero()`` (an nv zero vector) and ``sample.gravity`` (the gravity vector [m/s²]).
    """

    kind: ClassVar[str] = ""
    #: parameter name -> unit; order is the order of design variables (a routed spring's instance adds its cable).
    parameter_units: dict[str, str] = {}
    #: parameters that must be ≥ 0 (likewise).
    nonnegative: tuple[str, ...] = ()
    #: parameter name -> default value (None: the parameter is required).
    defaults: ClassVar[dict[str, float | None]] = {}
    #: parameters that the torque and the potential depend on linearly (the solver fits them
    #: exactly by linear least squares at every start). An instance may narrow this list.
    linear_parameters: tuple[str, ...] = ()
    #: the record keys that say where the element acts: ``("a", "b")`` (anchors) or ``("joint",)``.
    ends: ClassVar[tuple[str, ...]] = ()
    #: option key -> its type (a type annotation that the config schema validates against);
    #: the record keys of the options besides name, type, ends and parameters.
    option_types: ClassVar[dict[str, object]] = {}
    #: options a record must give (the others are optional).
    required_options: ClassVar[tuple[str, ...]] = ()
    #: the option keys (``tuple(option_types)``, set for every subclass).
    option_keys: ClassVar[tuple[str, ...]] = ()
    #: what the per-sample state and generalised force are, for reports: (name, unit).
    state_quantity: ClassVar[tuple[str, str]] = ("length", "m")
    force_quantity: ClassVar[tuple[str, str]] = ("tension", "N")

    #: ``True`` for the idealised law of a part that is also made as a real coil (its records say
    #: ``ideal: true``), ``False`` for the coil itself, ``None`` for laws without that choice.
    ideal: ClassVar[bool | None] = None
    #: the catalogue part this spring is (a stock spring; two-point laws take it as an option), or None
    part_number: str | None = None

    @classmethod
    def registry_key(cls) -> str:
        """The key of this law in :data:`SPRING_TYPES`: its ``kind``, or ``"<kind>:ideal"`` for an idealised law."""
        return f"{cls.kind}:ideal" if cls.ideal else cls.kind

    def __init_subclass__(cls, **kwargs: Any) -> None:
        """Register every law that names its ``kind`` in :data:`SPRING_TYPES` (the registry)."""
        super().__init_subclass__(**kwargs)
        cls.option_keys = tuple(cls.option_types)
        if cls.kind and (cls.__dict__.get("kind") or "ideal" in cls.__dict__):
            key = cls.registry_key()
            known = SPRING_TYPES.get(key)
            if known is not None and known.__qualname__ != cls.__qualname__:
                raise TypeError(
                    f"spring law {key!r} is defined twice: {known.__module__}.{known.__qualname__} "
                    f"and {cls.__module__}.{cls.__qualname__}"
                )
            SPRING_TYPES[key] = cls

    def __init__(self, name: str | None = None, **parameters: Any):
        self.name = name
        unknown = set(parameters) - set(self.parameter_units)
        if unknown:
            raise InputError(
                f"{type(self).__name__} {name or ''}: unknown parameter(s) {', '.join(sorted(unknown))}; "
                f"valid: {', '.join(self.parameter_units)}"
            )
        self.parameters: dict[str, float | Free] = {}
        for key in self.parameter_units:
            value = parameters.get(key, self.defaults.get(key))
            if value is None:
                raise InputError(f"{type(self).__name__} {name or ''}: parameter {key!r} is required")
            self.parameters[key] = _checked_parameter(self, key, value)

    # ---------------------------------------------------------------- what the element needs
    @property
    def anchors(self) -> dict[str, Anchor]:
        """Ends with (possibly free) anchor points, by end name (``{}`` for torsional springs)."""
        return {}

    @property
    def bodies(self) -> tuple[str, ...]:
        """Bodies whose placement and Jacobian the element needs."""
        return tuple(anchor.body for anchor in self.anchors.values())

    @property
    def joints(self) -> tuple[str, ...]:
        """Joints whose coordinate the element needs."""
        return ()

    def check(self, mechanism: Mechanism) -> None:  # noqa: B027  (a hook: a law without body or joint checks keeps it)
        """Raise :class:`~springbalance.errors.InputError` when the element does not fit ``mechanism``."""

    @abc.abstractmethod
    def contribution(self, sample: Sample, parameters: dict, points: dict) -> Contribution:
        """Torque, potential, state and generalised force at one sample.

        ``parameters`` maps parameter names to numbers or CasADi symbols; ``points`` maps each
        end of :attr:`anchors` to its body-frame point (3-vector, affine in the design variables).
        """

    # ---------------------------------------------------------------- constraints and records
    def constraints(self) -> list:
        """Practical constraints (docs/model.md §7) that apply to this spring."""
        return []

    def spring_mass(self, parameters: Parameters) -> Value:
        """The spring's own mass ``m_s`` [kg] for the given parameter values: 0 unless the law carries one."""
        return 0.0

    def part_mass(self, parameters: Parameters) -> Value:
        """The mass [kg] of the part itself, whether or not the model carries its weight (docs/model.md
        §5.1): a coil's wire, a given ``mass``, else 0 (numbers or CasADi expressions)."""
        return self.spring_mass(parameters)

    def derived_values(self, values: dict) -> dict:
        """The law's values that follow from the parameter values ``values`` [SI] (a coil's stiffness
        [N/m], free length [m], ...); none unless the law is a part built from other dimensions."""
        return {}

    def law_warnings(self, values: dict, lengths: np.ndarray, tolerance: float = 1e-6) -> list[str]:
        """Where a real part departs from this idealised law at the workspace states ``lengths``
        (length [m] or angle [rad]); none unless the law says so."""
        return []

    def options(self) -> dict:
        return {}

    def ends_to_dict(self) -> dict:
        return {end: anchor.to_dict() for end, anchor in self.anchors.items()}

    def to_dict(self) -> dict:
        record = {"name": self.name, "type": self.kind, **self.ends_to_dict()}
        for key, value in self.parameters.items():
            record[key] = value.to_dict() if isinstance(value, Free) else float(value)
        record.update(self.options())
        return record

    def _label(self) -> str:
        return f"{type(self).__name__} {self.name or ''}".strip()

    def _positive_stiffness(self, reason: str) -> None:
        """Reject a stiffness range that reaches 0 (``reason`` says what needs k > 0)."""
        stiffness = self.parameters["stiffness"]
        lowest = float(stiffness.lower) if isinstance(stiffness, Free) else float(stiffness)
        if lowest <= 0:
            raise InputError(
                f"{self._label()}: {reason} needs a stiffness > 0 (its lower bound is {lowest:g}); "
                "give stiffness a positive lower bound"
            )


def _checked_parameter(spring: Spring, key: str, value: Any) -> float | Free:
    label = f"{type(spring).__name__} {spring.name or ''}".strip()
    if isinstance(value, Free):
        if value.lower.shape != ():
            raise InputError(f"{label}: {key} must be a scalar Free, got bounds {value.lower.tolist()}")
        if key in spring.nonnegative and value.lower < 0:
            raise InputError(f"{label}: {key} lower bound must be ≥ 0, got {float(value.lower)}")
        return value
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{label}: {key} must be a number or Free, got {value!r}") from None
    if not np.isfinite(number):
        raise InputError(f"{label}: {key} must be finite, got {value!r}")
    if key in spring.nonnegative and number < 0:
        raise InputError(f"{label}: {key} must be ≥ 0, got {number}")
    return number


def _positive_option(spring: Spring, key: str, value: Any) -> float | None:
    if value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"spring {spring.name or ''}: {key} must be a number, got {value!r}") from None
    if not np.isfinite(number) or number <= 0:
        raise InputError(f"spring {spring.name or ''}: {key} must be a positive number, got {value!r}")
    return number
