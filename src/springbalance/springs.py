r"""Spring laws (MODEL.md §2). Each law is one small class.

A spring joins a point of body A to a point of body B (:class:`~springbalance.params.Anchor`).
With ``L`` the distance between the ends, the spring stores ``V_s(L)`` [J] and pulls the
ends together with tension ``F(L) = dV_s/dL`` [N] (negative for a spring that pushes).
Its share of the actuator torque at configuration ``q`` is

.. math:: \tau_s(q) = F(L)\,(J_{p_b} - J_{p_a})^T u,\qquad u = (x_b - x_a)/L .

Laws are written with plain arithmetic, so one implementation serves CasADi symbols
(inside the optimiser) and NumPy arrays (checks, reports). ``parameters`` maps each
parameter name to its value. Every parameter is a number or :class:`~springbalance.params.Free`.
"""

from __future__ import annotations

import abc

from typing import ClassVar

import numpy as np

from . import constraints as practical
from .errors import InputError
from .params import Anchor, Free


class Spring(abc.ABC):
    """Base class of two-point springs. Subclasses set ``kind``, ``parameter_units`` and the law."""

    kind: ClassVar[str] = ""
    #: parameter name -> unit; order is the order of design variables.
    parameter_units: ClassVar[dict[str, str]] = {}
    #: parameters that must be ≥ 0.
    nonnegative: ClassVar[tuple[str, ...]] = ()
    defaults: ClassVar[dict[str, float]] = {}
    #: parameters that the tension F(L), hence the torque and the potential, depend on linearly
    #: (the solver fits them exactly by linear least squares at every start).
    linear_parameters: ClassVar[tuple[str, ...]] = ()

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, *, max_force: float | None = None,
                 max_length: float | None = None, min_length: float | None = None, **parameters):
        if not isinstance(a, Anchor) or not isinstance(b, Anchor):
            raise InputError(f"spring {name or ''!s}: ends must be Anchor objects, got {a!r} and {b!r}")
        self.a, self.b, self.name = a, b, name
        unknown = set(parameters) - set(self.parameter_units)
        if unknown:
            raise InputError(f"{type(self).__name__} {name or ''}: unknown parameter(s) {', '.join(sorted(unknown))}; "
                             f"valid: {', '.join(self.parameter_units)}")
        self.parameters: dict[str, float | Free] = {}
        for key in self.parameter_units:
            value = parameters.get(key, self.defaults.get(key))
            if value is None:
                raise InputError(f"{type(self).__name__} {name or ''}: parameter {key!r} is required")
            self.parameters[key] = _checked_parameter(self, key, value)
        self.max_force = _positive_option(self, "max_force", max_force)
        self.max_length = _positive_option(self, "max_length", max_length)
        self.min_length = _positive_option(self, "min_length", min_length)

    # ---------------------------------------------------------------- the law
    @abc.abstractmethod
    def tension(self, length, parameters):
        """Tension ``F(L)`` [N], positive when the spring pulls its ends together."""

    @abc.abstractmethod
    def potential(self, length, parameters):
        """Stored energy ``V_s(L)`` [J]."""

    def tension_per_length(self, length, parameters):
        """``F(L) / L`` [N/m]; the force on end b is ``-(F/L) d`` with ``d = x_b - x_a``."""
        return self.tension(length, parameters) / length

    # ---------------------------------------------------------------- constraints
    def constraints(self) -> list:
        """Practical constraints (MODEL.md §6) that apply to this spring."""
        rows = []
        if self.max_force is not None:
            rows.append(practical.MaxForce(self.max_force))
        if self.max_length is not None:
            rows.append(practical.MaxLength(self.max_length))
        if self.min_length is not None:
            rows.append(practical.MinLength(self.min_length))
        return rows

    # ---------------------------------------------------------------- records
    def options(self) -> dict:
        return {key: value for key, value in (("max_force", self.max_force), ("max_length", self.max_length),
                                              ("min_length", self.min_length)) if value is not None}

    def to_dict(self) -> dict:
        record = {"name": self.name, "type": self.kind, "a": self.a.to_dict(), "b": self.b.to_dict()}
        for key, value in self.parameters.items():
            record[key] = value.to_dict() if isinstance(value, Free) else float(value)
        record.update(self.options())
        return record

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, {self.a!r} -> {self.b!r})"


class ZeroFreeLengthSpring(Spring):
    r"""Zero-free-length spring: :math:`F = k L`, :math:`V_s = k L^2 / 2`.

    Parameters: ``stiffness`` k [N/m].
    """

    kind = "zero_free_length"
    parameter_units = {"stiffness": "N/m"}
    nonnegative = ("stiffness",)
    linear_parameters = ("stiffness",)

    def tension(self, length, parameters):
        return parameters["stiffness"] * length                       # [N/m]·[m] = [N]

    def potential(self, length, parameters):
        return 0.5 * parameters["stiffness"] * length * length        # [N/m]·[m²] = [J]

    def tension_per_length(self, length, parameters):
        return parameters["stiffness"] + 0 * length                   # smooth at L = 0


class ExtensionSpring(Spring):
    r"""Linear extension spring with initial tension:

    .. math:: F = F_0 + k (L - l_0),\qquad V_s = F_0 (L - l_0) + k (L - l_0)^2 / 2 .

    Parameters: ``stiffness`` k [N/m], ``free_length`` l0 [m], ``initial_tension`` F0 [N]
    (default 0). Options: ``keep_tension`` (default True: ``L ≥ l0`` at every sample, a
    coil spring cannot be compressed below its free length), ``max_stretch`` ratio ρ
    (``L ≤ ρ l0``), ``max_force`` [N], ``max_length`` / ``min_length`` [m].
    """

    kind = "extension"
    parameter_units = {"stiffness": "N/m", "free_length": "m", "initial_tension": "N"}
    nonnegative = ("stiffness", "free_length", "initial_tension")
    defaults = {"initial_tension": 0.0}
    linear_parameters = ("stiffness", "initial_tension")

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, *, keep_tension: bool = True,
                 max_stretch: float | None = None, **kwargs):
        super().__init__(a, b, name, **kwargs)
        self.keep_tension = bool(keep_tension)
        self.max_stretch = _positive_option(self, "max_stretch", max_stretch)
        if self.max_stretch is not None and self.max_stretch <= 1:
            raise InputError(f"spring {name or ''}: max_stretch is a ratio L/l0 and must exceed 1, got {max_stretch}")

    def tension(self, length, parameters):
        stretch = length - parameters["free_length"]                          # [m]
        return parameters["initial_tension"] + parameters["stiffness"] * stretch  # [N]

    def potential(self, length, parameters):
        stretch = length - parameters["free_length"]                          # [m]
        return stretch * (parameters["initial_tension"] + 0.5 * parameters["stiffness"] * stretch)  # [J]

    def constraints(self) -> list:
        rows = super().constraints()
        if self.keep_tension:
            rows.insert(0, practical.StaysInTension())
        if self.max_stretch is not None:
            rows.append(practical.MaxStretch(self.max_stretch))
        return rows

    def options(self) -> dict:
        record = super().options()
        record["keep_tension"] = self.keep_tension
        if self.max_stretch is not None:
            record["max_stretch"] = self.max_stretch
        return record


#: spring ``type`` name in configs and saved designs -> class.
SPRING_TYPES: dict[str, type[Spring]] = {cls.kind: cls for cls in (ExtensionSpring, ZeroFreeLengthSpring)}


def _checked_parameter(spring: Spring, key: str, value):
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


def _positive_option(spring: Spring, key: str, value):
    if value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"spring {spring.name or ''}: {key} must be a number, got {value!r}") from None
    if not np.isfinite(number) or number <= 0:
        raise InputError(f"spring {spring.name or ''}: {key} must be a positive number, got {value!r}")
    return number


_SPRING_OPTIONS = ("max_force", "max_length", "min_length")
_EXTENSION_OPTIONS = ("keep_tension", "max_stretch")


def spring_from_dict(record, where: str = "spring") -> Spring:
    """Build a spring from its record (as in configs and saved designs).

    ``{name?, type, a: anchor, b: anchor, <parameters>, <options>}`` where each parameter is a
    number or ``{lower, upper, init?}``.
    """
    from .params import anchor_from_dict, check_keys, value_from_record

    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping, got {record!r}")
    kind = record.get("type", "extension")
    if not isinstance(kind, str) or kind not in SPRING_TYPES:
        raise InputError(f"{where}.type: unknown spring type {kind!r}; valid: {', '.join(SPRING_TYPES)}")
    cls = SPRING_TYPES[kind]
    options = _SPRING_OPTIONS + (_EXTENSION_OPTIONS if issubclass(cls, ExtensionSpring) else ())
    check_keys(record, ("name", "type", "a", "b", *cls.parameter_units, *options), where)
    name = record.get("name")
    where = f"{where} {name!r}" if name else where
    for end in ("a", "b"):
        if end not in record:
            raise InputError(f"{where}: missing key {end!r} (the anchor of that end)")
    a = anchor_from_dict(record["a"], f"{where}.a")
    b = anchor_from_dict(record["b"], f"{where}.b")
    parameters = {key: value_from_record(record[key], f"{where}.{key}") for key in cls.parameter_units if key in record}
    extra = {key: record[key] for key in options if key in record}
    if not isinstance(extra.get("keep_tension", True), bool):
        raise InputError(f"{where}.keep_tension: expected true or false, got {extra['keep_tension']!r}")
    try:
        return cls(a, b, None if name is None else str(name), **parameters, **extra)
    except InputError as error:
        raise InputError(f"{where}: {error}") from None
