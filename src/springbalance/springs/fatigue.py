r"""Fatigue of helical coil springs under a cycling force (docs/model.md §3.8.2): the duty, the
fatigue data, the criteria and the safety factor per location (Shigley, *Mechanical Engineering
Design*, Budynas & Nisbett, 9th/10th ed., §10-9 and §10-12).

A preloaded spring's force cycles between ``F_min`` and ``F_max`` [N] (magnitudes, ``F_min ≥ 0``).
At a location with stress per newton ``c`` [Pa/N] (body: :math:`K_B 8 D/(\pi d^3)`; hook A:
:math:`(K)_A 16 D/(\pi d^3) + 4/(\pi d^2)`; hook B: :math:`(K)_B 8 D/(\pi d^3)`) the stress
amplitude and mean are :math:`\tau_a = c (F_{max} - F_{min})/2` and :math:`\tau_m = c (F_{max} + F_{min})/2`.

Fatigue data, one point ``(S_a, S_m)`` of the fatigue locus each:

- Zimmerli (infinite life, spring steels under 10 mm, any material): ``S_sa = 241``,
  ``S_sm = 379`` MPa unpeened; ``398``, ``534`` MPa peened (Shigley Eq. 10-28);
- Shigley Table 10-8 (Associated Spring; extension springs of ASTM A228 and 302 stainless, not
  peened, stress ratio 0): the range ``S_r`` as a fraction of ``S_ut`` at 10⁵, 10⁶, 10⁷ cycles,
  body torsion 36/33/30 %, hook torsion 34/30/28 %, hook bending 51/47/45 %; the point is
  ``S_a = S_m = S_r/2``.

The ultimate strength is :math:`S_{su} = 0.67 S_{ut}` in torsion (Shigley Eq. 10-30) and
:math:`S_{ut}` in bending. The criterion projects the point to zero mean stress:
Gerber :math:`S_e = S_a / (1 - (S_m/S_u)^2)`, Goodman :math:`S_e = S_a / (1 - S_m/S_u)`
(Sines: :math:`S_e = S_a`, the mean stress ignored), times the reliability factor ``k_e``
(Shigley Table 6-5). Along the load line through the origin the safety factor is

.. math::
    n_f^{Goodman} = \Bigl(\frac{\tau_a}{S_e} + \frac{\tau_m}{S_u}\Bigr)^{-1},\qquad
    n_f^{Gerber} = \frac{1}{2}\Bigl(\frac{S_u}{\tau_m}\Bigr)^2 \frac{\tau_a}{S_e}
        \Bigl[-1 + \sqrt{1 + \Bigl(\frac{2 \tau_m S_e}{S_u \tau_a}\Bigr)^2}\Bigr],\qquad
    n_f^{Sines} = S_e/\tau_a

(Shigley Table 6-7), and ``n_f ≥ n`` is the row :func:`damage_row` ``≥ 0`` of the optimisation.
Every quantity is in SI units (m, N, Pa).
"""

from __future__ import annotations

import dataclasses
import math
import typing
from typing import Any, Mapping

import numpy as np

from springbalance.errors import InputError
from springbalance.springs.helical_formulas import HOOK_SIDE_BEND_INDEX, MPA, bergstrasser_factor
from springbalance.springs.materials import Material, material_named, spring_kind

#: Zimmerli's endurance point (S_sa, S_sm) [Pa], unpeened and peened (Shigley Eq. 10-28)
ZIMMERLI = {False: (241.0 * MPA, 379.0 * MPA), True: (398.0 * MPA, 534.0 * MPA)}
#: Shigley Table 10-8: the stress range S_r as a fraction of S_ut (stress ratio 0), per cycle count and location
CYCLE_TABLE = {
    1e5: {"body": 0.36, "hook_torsion": 0.34, "hook_bending": 0.51},
    1e6: {"body": 0.33, "hook_torsion": 0.30, "hook_bending": 0.47},
    1e7: {"body": 0.30, "hook_torsion": 0.28, "hook_bending": 0.45},
}
#: reliability -> factor k_e on the endurance strength (Shigley Table 6-5; 0.5: the data as published)
RELIABILITY = {0.5: 1.000, 0.9: 0.897, 0.95: 0.868, 0.99: 0.814, 0.999: 0.753, 0.9999: 0.702}
#: the criteria that project a fatigue point to zero mean stress
CRITERIA = ("gerber", "goodman", "sines")
#: ultimate shear strength over tensile strength (Shigley Eq. 10-30)
SHEAR_ULTIMATE = 0.67
#: the name of a coil's auxiliary variable: a lower bound [N] on its force over every sample (docs/model.md §3.8.2)
FLOOR = "fatigue_min_force"
#: the name of a coil's auxiliary variable: an upper bound [N] on its force over every sample (docs/model.md §3.8.2)
CEILING = "fatigue_max_force"
#: the locations of each kind of coil
LOCATIONS = {"extension": ("body", "hook_bending", "hook_torsion"), "compression": ("body",)}
INFINITE = math.inf
#: the config record of a duty (resolved by the config schema, like the ``helical`` option)
DUTY_OPTION = typing.ForwardRef("DutyOption", module="springbalance.springs.options")


@dataclasses.dataclass(frozen=True)
class Duty:
    """What a coil must survive (the ``duty`` record of a coil).

    Attributes:
        cycles: load cycles the spring must live [1]; ``inf`` (config ``infinite``) for infinite life. Default
            10⁶: an arm that moves once every 10 s through an 8-hour shift, 250 days a year, cycles its springs
            7·10⁵ times a year.
        peened: shot-peened wire (compression springs only: a close-wound extension spring cannot be peened).
        reliability: the probability the data hold (a key of :data:`RELIABILITY`); 0.5 uses the data as published.
        safety_factor: the fatigue safety factor ``n_f`` every location must reach [1] (default 1.2).
        criterion: "gerber" (default), "goodman" or "sines".
    """

    cycles: float = 1e6
    peened: bool = False
    reliability: float = 0.5
    safety_factor: float = 1.2
    criterion: str = "gerber"

    def __post_init__(self) -> None:
        cycles = self.cycles
        if isinstance(cycles, bool) or not isinstance(cycles, (int, float)) or not (cycles >= 1):
            raise InputError(f"duty.cycles: expected a number ≥ 1 or 'infinite', got {cycles!r}")
        if not isinstance(self.peened, bool):
            raise InputError(f"duty.peened: expected true or false, got {self.peened!r}")
        if self.reliability not in RELIABILITY or isinstance(self.reliability, bool):
            raise InputError(
                f"duty.reliability: {self.reliability!r} has no factor; valid: {', '.join(map(str, RELIABILITY))} "
                "(Shigley Table 6-5)"
            )
        n = self.safety_factor
        if isinstance(n, bool) or not isinstance(n, (int, float)) or not (math.isfinite(n) and n >= 1):
            raise InputError(f"duty.safety_factor: expected a number ≥ 1, got {n!r}")
        if self.criterion not in CRITERIA:
            raise InputError(f"duty.criterion: expected one of {', '.join(CRITERIA)}, got {self.criterion!r}")

    def to_dict(self) -> dict[str, Any]:
        """The config record (``cycles: infinite`` for infinite life)."""
        record = dataclasses.asdict(self)
        record["cycles"] = "infinite" if math.isinf(self.cycles) else float(self.cycles)
        return record

    def check_kind(self, kind: str, where: str = "duty") -> Duty:
        """``self`` for a coil of ``kind``; InputError when an extension spring is said to be peened."""
        if spring_kind(kind) == "extension" and self.peened:
            raise InputError(f"{where}.peened: true, but a close-wound extension spring cannot be shot-peened")
        return self


def duty_from_record(record: Any, where: str = "duty") -> Duty:
    """``{cycles?, peened?, reliability?, safety_factor?, criterion?}`` (or a :class:`Duty`) → :class:`Duty`."""
    if isinstance(record, Duty):
        return record
    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping {{cycles, peened, reliability, safety_factor, criterion}}")
    valid = [field.name for field in dataclasses.fields(Duty)]
    unknown = [key for key in record if key not in valid]
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r}; valid keys: {', '.join(valid)}")
    values = dict(record)
    if isinstance(values.get("cycles"), str):
        if values["cycles"].strip().lower() not in ("infinite", "inf"):
            raise InputError(f"{where}.cycles: expected a number ≥ 1 or 'infinite', got {values['cycles']!r}")
        values["cycles"] = INFINITE
    try:
        return Duty(**values)
    except InputError as error:
        raise InputError(f"{where}{str(error)[4:]}") from None


# ---------------------------------------------------------------------- data and criteria
@dataclasses.dataclass(frozen=True)
class FatiguePoint:
    """One fatigue-locus point ``(S_a, S_m)`` [Pa], the ultimate strength ``S_u`` [Pa] it projects to, and the
    life it stands for (cycles; ``inf`` for Zimmerli's infinite life)."""

    amplitude: Any
    mean: Any
    ultimate: Any
    life: float
    source: str

    def endurance(self, criterion: str, factor: float = 1.0) -> Any:
        """``S_e`` [Pa]: the point projected to zero mean stress by ``criterion``, times ``factor`` (k_e)."""
        ratio = self.mean / self.ultimate
        if criterion == "gerber":
            return factor * self.amplitude / (1.0 - ratio * ratio)
        if criterion == "goodman":
            return factor * self.amplitude / (1.0 - ratio)
        return factor * self.amplitude


def fatigue_point(material: Material, wire_diameter: Any, location: str, life: float, peened: bool) -> FatiguePoint:
    """The fatigue data of ``location`` for a life of ``life`` cycles: Zimmerli's point for the body at
    infinite life (and for a peened body at any life), else Table 10-8's column of the
    smallest listed life ≥ ``life`` (its last, 10⁷, beyond). ``wire_diameter`` [m] may be a CasADi expression."""
    strength = material.tensile_strength(wire_diameter)  # S_ut [Pa]
    ultimate = strength if location == "hook_bending" else SHEAR_ULTIMATE * strength
    if location == "body" and (math.isinf(life) or peened):
        amplitude, mean = ZIMMERLI[peened]
        return FatiguePoint(amplitude, mean, ultimate, INFINITE, "Zimmerli" + (" (peened)" if peened else ""))
    column = next((cycles for cycles in CYCLE_TABLE if life <= cycles), 1e7)
    half = 0.5 * CYCLE_TABLE[column][location] * strength  # S_r / 2 [Pa]
    return FatiguePoint(half, half, ultimate, column, f"Shigley Table 10-8, {column:.0e} cycles")


def safety_factor(amplitude: float, mean: float, point: FatiguePoint, criterion: str, factor: float = 1.0) -> float:
    """``n_f`` [1] of stress amplitude ``amplitude`` and mean ``mean`` [Pa] on the load line through the origin
    (Shigley Table 6-7); ``inf`` without stress."""
    endurance, ultimate = float(point.endurance(criterion, factor)), float(point.ultimate)
    if amplitude <= 0 and mean <= 0:
        return INFINITE
    if criterion == "sines":
        return endurance / amplitude if amplitude > 0 else INFINITE
    if criterion == "goodman":
        return 1.0 / (amplitude / endurance + mean / ultimate)
    if mean <= 0:
        return endurance / amplitude
    if amplitude <= 0:
        return ultimate / mean
    ratio = 2.0 * mean * endurance / (ultimate * amplitude)
    return 0.5 * (ultimate / mean) ** 2 * (amplitude / endurance) * (-1.0 + math.sqrt(1.0 + ratio * ratio))


def damage_row(amplitude: Any, mean: Any, point: FatiguePoint, criterion: str, required: float, factor: float) -> Any:
    """The row ``≥ 0`` iff ``n_f ≥ required`` (numbers or CasADi): Goodman ``1 − n (τ_a/S_e + τ_m/S_u)``,
    Gerber ``1 − n τ_a/S_e − (n τ_m/S_u)²``, Sines ``1 − n τ_a/S_e`` [1]."""
    endurance, ultimate = point.endurance(criterion, factor), point.ultimate
    if criterion == "goodman":
        return 1 - required * (amplitude / endurance + mean / ultimate)
    if criterion == "gerber":
        scaled = required * mean / ultimate
        return 1 - required * amplitude / endurance - scaled * scaled
    return 1 - required * amplitude / endurance


def stress_per_force(
    location: str,
    wire_diameter: Any,
    mean_diameter: Any,
    hook_index: Any = None,
    side_bend_index: float = HOOK_SIDE_BEND_INDEX,
) -> Any:
    """``c`` [Pa/N]: the stress at ``location`` per newton of axial force (Shigley Eq. 10-7, 10-34 to 10-36;
    hook bend index ``C_1 = 2 r_1/d`` (default ``D/d``, a hook as wide as the coil), side bend ``C_2 = 2 r_2/d``
    (default :data:`HOOK_SIDE_BEND_INDEX`))."""
    d, D = wire_diameter, mean_diameter
    if location == "body":
        return bergstrasser_factor(D / d) * 8 * D / (math.pi * d**3)
    if location == "hook_bending":
        c1 = D / d if hook_index is None else hook_index
        return (4 * c1 * c1 - c1 - 1) / (4 * c1 * (c1 - 1)) * 16 * D / (math.pi * d**3) + 4 / (math.pi * d**2)
    c2 = side_bend_index
    return (4 * c2 - 1) / (4 * c2 - 4) * 8 * D / (math.pi * d**3)


# ---------------------------------------------------------------------- margins of a part
@dataclasses.dataclass(frozen=True)
class Margin:
    """The fatigue verdict of one location: stresses [Pa], the data used, ``n_f`` at the duty's cycles, and the
    longest life (cycles, ``inf``: Zimmerli's infinite life) at which ``n_f`` still reaches the required factor
    (0 when not even 10⁵)."""

    location: str
    amplitude: float
    mean: float
    endurance: float
    ultimate: float
    source: str
    safety_factor: float
    required: float
    life: float
    #: whether finite-life data exist for the location (Table 10-8: unpeened springs only)
    finite_data: bool = True

    @property
    def holds(self) -> bool:
        return self.safety_factor >= self.required

    def life_text(self) -> str:
        """``"infinite (Zimmerli)"``, ``"≥ 1e+07 cycles"`` … ``"< 1e+05 cycles"``."""
        if math.isinf(self.life):
            return "infinite (Zimmerli)"
        if not self.finite_data:
            return "short of infinite life (Zimmerli); no finite-life data for this spring"
        return f"≥ {self.life:.0e} cycles" if self.life > 0 else f"< {min(CYCLE_TABLE):.0e} cycles"

    def to_dict(self) -> dict[str, Any]:
        record = dataclasses.asdict(self)
        for key in ("safety_factor", "life"):
            record[key] = None if math.isinf(record[key]) else record[key]
        record["life_text"] = self.life_text()
        return record


def fatigue_margins(
    wire_diameter: float,
    mean_diameter: float,
    material: str | Material,
    min_force: float,
    max_force: float,
    duty: Duty | Mapping[str, Any] | None = None,
    kind: str = "extension",
    hook_index: float | None = None,
    side_bend_index: float = HOOK_SIDE_BEND_INDEX,
) -> dict[str, Margin]:
    """The fatigue margin of every location of a helical coil (``kind`` "extension": body, hook A bending, hook
    B torsion; "compression": body) whose force magnitude cycles between ``min_force`` and ``max_force`` [N]
    (``0 ≤ min ≤ max``), wire ``d`` and mean coil diameter ``D`` [m], under ``duty`` (default :class:`Duty`).
    ``hook_index``, ``side_bend_index``: the hook's bend indices (:func:`stress_per_force`).

    This is what a bought part is checked with: its geometry, its material and the force range it sees."""
    duty = (Duty() if duty is None else duty if isinstance(duty, Duty) else duty_from_record(dict(duty))).check_kind(
        kind
    )
    material = material_named(material)
    low, high = float(min_force), float(max_force)
    if not (0 <= low <= high and math.isfinite(high)):
        raise InputError(f"fatigue needs 0 ≤ min_force ≤ max_force, got {min_force!r} and {max_force!r}")
    factor = RELIABILITY[duty.reliability]
    margins = {}
    for location in LOCATIONS[kind]:
        c = float(stress_per_force(location, wire_diameter, mean_diameter, hook_index, side_bend_index))
        amplitude, mean = 0.5 * c * (high - low), 0.5 * c * (high + low)
        point = fatigue_point(material, wire_diameter, location, duty.cycles, duty.peened)
        n = safety_factor(amplitude, mean, point, duty.criterion, factor)
        # finite lives from Table 10-8's columns (its body column serves a compression body too, as the data
        # at the duty's cycles do); a peened spring has Zimmerli's infinite-life point only
        lives = [INFINITE] if duty.peened else [INFINITE, *sorted(CYCLE_TABLE, reverse=True)]
        if location != "body":
            lives = lives[1:]
        life = 0.0
        for candidate in lives:
            data = fatigue_point(material, wire_diameter, location, candidate, duty.peened)
            if safety_factor(amplitude, mean, data, duty.criterion, factor) >= duty.safety_factor:
                life = candidate
                break
        margins[location] = Margin(
            location,
            amplitude,
            mean,
            float(point.endurance(duty.criterion, factor)),
            float(point.ultimate),
            point.source,
            n,
            duty.safety_factor,
            life,
            finite_data=not duty.peened,
        )
    return margins


def force_range(forces: np.ndarray, kind: str) -> tuple[float, float]:
    """``(F_min, F_max)`` [N] of a coil's force magnitude over the samples (tension, or the push of a
    compression spring), at least 0."""
    load = np.asarray(forces, dtype=float) * (1.0 if kind == "extension" else -1.0)
    if load.size == 0:
        return 0.0, 0.0
    return max(float(np.min(load)), 0.0), max(float(np.max(load)), 0.0)
