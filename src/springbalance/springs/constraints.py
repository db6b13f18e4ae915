"""Practical constraints on a spring (docs/model.md §7), one small class each.

Each constraint produces, for every workspace sample, rows that must be ``≥ 0`` at a
feasible design: ``rows(state, force, parameters)`` with the spring's per-sample state
(length ``L`` [m], or joint angle [rad] for a torsional spring), its generalised force
(tension [N] or torque [N·m]) and its parameter values. They are written with plain
arithmetic so that the same code evaluates CasADi expressions (inside the NLP) and NumPy
arrays (when checking a design). A constraint gives one row per sample (``name``,
``unit``, ``scale``), or several when it has ``parts``: a tuple of ``(name, unit, scale)``,
and ``rows`` then returns one expression per part.
Bounds on stiffness and free length are variable bounds (:class:`~springbalance.springs.params.Free`).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Union

from springbalance.springs.helical_option import Helical
from springbalance.springs.values import Parameters, ValueT


@dataclasses.dataclass(frozen=True)
class StaysInTension:
    """A tension spring never goes slack: ``L - l0 ≥ 0`` at every sample [m]."""

    name = "tension"
    unit = "m"
    scale = 0.1  # [m] typical size of a violation, for the solver's scaling

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        return length - parameters["free_length"]


@dataclasses.dataclass(frozen=True)
class MaxStretch:
    """A spring is not stretched beyond ``ratio`` times its free length: ``ρ l0 - L ≥ 0`` [m]."""

    ratio: float
    name = "max_stretch"
    unit = "m"
    scale = 0.1  # [m]

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        return self.ratio * parameters["free_length"] - length


@dataclasses.dataclass(frozen=True)
class MaxForce:
    """The spring force stays within ``limit`` in magnitude: ``F_max - |F| ≥ 0`` [N].

    Written as ``F_max² - F² ≥ 0`` scaled by ``1/F_max`` so that it is smooth.
    """

    limit: float
    name = "max_force"
    unit = "N"

    @property
    def scale(self) -> float:
        return self.limit  # [N]

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        return (self.limit * self.limit - force * force) / self.limit


@dataclasses.dataclass(frozen=True)
class MaxLength:
    """The spring (with its fittings) is never longer than ``limit``: ``L_max - L ≥ 0`` [m]."""

    limit: float
    name = "max_length"
    unit = "m"

    @property
    def scale(self) -> float:
        return self.limit  # [m]

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        return self.limit - length


@dataclasses.dataclass(frozen=True)
class FitsSegment:
    """A routed spring's body (with its fittings) fits on its segment: ``|P_1 - P_0| - L ≥ 0`` [m]
    (the cable then spans the rest of the path)."""

    name = "fits_segment"
    unit = "m"
    scale = 0.01  # [m]
    uses_extra = True

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters, extra: Any) -> ValueT | list[ValueT]:
        return extra["segment"] - length


@dataclasses.dataclass(frozen=True)
class MinLength:
    """The spring is never shorter than ``limit``: ``L - L_min ≥ 0`` [m]."""

    limit: float
    name = "min_length"
    unit = "m"

    @property
    def scale(self) -> float:
        return self.limit  # [m]

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        return length - self.limit


@dataclasses.dataclass(frozen=True)
class StaysCompressed:
    """A compression or gas spring stays compressed (in contact): ``l0 - L ≥ 0`` [m]."""

    name = "compressed"
    unit = "m"
    scale = 0.1  # [m]

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        return parameters["free_length"] - length


@dataclasses.dataclass(frozen=True)
class Stroke:
    """A compression or gas spring is not compressed beyond its stroke: ``L - (l0 - s) ≥ 0`` [m]."""

    stroke: float
    name = "stroke"
    unit = "m"
    scale = 0.1  # [m]

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        return length - (parameters["free_length"] - self.stroke)


@dataclasses.dataclass(frozen=True)
class MaxTorque(MaxForce):
    """A torsional spring's torque stays within ``limit``: ``(T_max² - T²)/T_max ≥ 0`` [N·m]."""

    name = "max_torque"
    unit = "N·m"


@dataclasses.dataclass(frozen=True)
class MaxDeflection:
    """A torsional spring turns at most ``limit`` from its neutral angle:
    ``(δ_max² - (q - q0)²)/δ_max ≥ 0`` [rad]."""

    limit: float
    name = "max_deflection"
    unit = "rad"

    @property
    def scale(self) -> float:
        return self.limit  # [rad]

    def rows(self, angle: ValueT, torque: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        deflection = angle - parameters["neutral_angle"]
        return (self.limit * self.limit - deflection * deflection) / self.limit


@dataclasses.dataclass(frozen=True)
class HelicalSpringExists:
    r"""A helical spring of the option's material and index ``C`` realises the design (exact).

    With ``n = G d/(8 C³ k)`` active coils, the coil length grows with the wire diameter
    ``d`` and the force a wire carries, :math:`F_{allow}(d) = \pi f S_{ut}(d) d^2/(8 K_W C)`,
    grows too (:class:`~springbalance.springs.sizing.Helical`). ``room`` is the length the coil
    must fit in: the free length ``l0`` (extension spring with hooks) or the working length
    ``L`` (compression spring, solid length), and ``d_fit(room, k)`` the largest wire that
    fits. A feasible wire exists iff ``d* = min(d_fit, d_max)`` carries ``|F|``, leaves room
    for ``n_min`` coils, and is not thinner than the material's thinnest wire ``d_min``:

    - ``helical_stress``: :math:`(F_{allow}(d_{fit})^2 - F^2)/F_{ref} \ge 0` [N];
    - ``helical_max_wire``: :math:`(F_{allow}(d_{max})^2 - F^2)/F_{ref} \ge 0` [N];
    - ``helical_coils``: :math:`d_{fit} - 8 C^3 k n_{min}/G \ge 0` [m];
    - ``helical_min_wire``: :math:`d_{fit} - d_{min} \ge 0` [m];
    - ``helical_max_stiffness``: :math:`k_{max} - k \ge 0` with :math:`k_{max} = G d_{max}/(8 C^3 n_{min})` [N/m].

    Per sample these rows are equivalent to the existence of the spring: for an extension
    spring ``room`` is the same at every sample, and for a compression spring the largest
    force and the shortest length occur at the same sample. Needs ``k > 0``.
    """

    helical: Helical
    kind: str  # "extension" or "compression"

    @property
    def parts(self) -> tuple[tuple[str, str, float], ...]:
        force_scale = self.helical.allowable_force(self.helical.material.diameter_range[1], self.kind) / 10  # [N]
        return (
            ("helical_stress", "N", force_scale),
            ("helical_max_wire", "N", force_scale),
            ("helical_coils", "m", 1e-3),
            ("helical_min_wire", "m", 1e-3),
            ("helical_max_stiffness", "N/m", self.helical.max_stiffness),
        )

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        helical, kind = self.helical, self.kind
        stiffness = parameters["stiffness"]  # [N/m]
        room = parameters["free_length"] if kind == "extension" else length  # [m]
        fit = helical.fitting_wire(room, stiffness, kind)  # d_fit [m]
        thinnest, thickest = helical.material.diameter_range  # [m]
        force_scale = self.parts[0][2]
        return [
            (helical.allowable_force(fit, kind) ** 2 - force * force) / force_scale,
            (helical.allowable_force(thickest, kind) ** 2 - force * force) / force_scale,
            fit - helical.coil_wire(stiffness),
            fit - thinnest,
            helical.max_stiffness - stiffness,
        ]


#: any practical constraint of this module (what :meth:`~springbalance.springs.laws.spring.Spring.constraints` lists)
Constraint = Union[
    StaysInTension,
    MaxStretch,
    MaxForce,
    MaxLength,
    FitsSegment,
    MinLength,
    StaysCompressed,
    Stroke,
    MaxTorque,
    MaxDeflection,
    HelicalSpringExists,
]
