r"""The springs' own mass against the least that can balance the arm (docs/model.md §5.1).

A helical coil whose body reaches the allowable shear stress ``τ_a`` [Pa] (Bergsträsser-corrected) stores at
most, per kilogram of its wire,

.. math:: u = \frac{(\tau_a / K_B)^2}{4 G \rho}\,\frac{n}{n + 2} \quad [\mathrm{J/kg}],

(``G`` [Pa], ``ρ`` [kg/m³], index ``C``, ``K_B = (4C + 2)/(4C − 3)``, ``n`` active of ``n + 2`` coils), and
springs that balance the arm exactly exchange at least the swing ``ΔV = max V_g − min V_g`` [J] of its gravity
potential over the workspace. So no set of coils that balances it weighs less than the *floor*
:math:`m_{floor} = \Delta V / \max_s u_s` [kg], each coil's ``u_s`` taken at the best its bounds allow: its
thinnest wire (the strongest, ``S_ut = A/d^m``), its largest index and its most coils.

A coil with a ``duty`` must also live its load cycles: its force cycles between ``F_min`` and ``F_max`` and
the energy it exchanges is :math:`(F_{max}^2 - F_{min}^2)/(2k)`, so its ``u`` is the static one times
:func:`fatigue_energy_fraction`, the largest :math:`(F_{max}^2 - F_{min}^2)/F_s^2` that every location's
fatigue safety factor allows (``F_s``: the force at the body's static allowable stress). For music wire at
10⁶ cycles that is about a third.

:func:`spring_mass` gives a design's record (:class:`SpringMass`): the parts' masses
(:meth:`~springbalance.springs.laws.Spring.part_mass`: a coil's wire, a given ``mass``, else 0), their total,
the floor and the arm's moving mass. :func:`check_mass_bound` says before a solve when ``max_spring_mass``
is below the lightest springs the bounds allow. Units: kg, J, Pa, m.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping, Protocol, Sequence

import numpy as np

from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace
from springbalance.springs.fatigue import Duty, fatigue_margins
from springbalance.springs.helical_formulas import bergstrasser_factor
from springbalance.springs.laws import Spring
from springbalance.springs.laws.coil import HelicalCoilSpring
from springbalance.springs.materials import KINDS, MATERIALS, Material
from springbalance.springs.params import Free

#: the index at which a design without coils takes the listed wires' energy per kilogram (the default
#: ``index_range``'s upper end), and the limit ``n/(n + 2) → 1`` of many coils
DEFAULT_INDEX = 12.0


class _Model(Protocol):
    """What :func:`spring_mass` reads of a problem's torque model."""

    def spring_values(self, spring: Spring, x: np.ndarray, scenario: int = 0) -> dict: ...


class _Problem(Protocol):
    """What this module reads of a :class:`~springbalance.design.problem.DesignProblem`."""

    @property
    def springs(self) -> Sequence[Spring]: ...

    @property
    def mechanism(self) -> Mechanism: ...

    @property
    def workspace(self) -> Workspace: ...

    @property
    def model(self) -> _Model: ...

    @property
    def max_spring_mass(self) -> float | None: ...


@dataclasses.dataclass(frozen=True)
class SpringMass:
    """A design's spring mass against the floor and the arm.

    Attributes:
        springs: each spring's part mass [kg] (0 for an ideal spring without ``mass``).
        floor: the least mass of coils that balance the arm exactly [kg] (docs/model.md §5.1).
        energy_swing: ``ΔV``, the swing of the unbalanced arm's gravity potential over the workspace
            (the largest of the scenarios') [J].
        energy_per_kg: the best ``u`` of the design's coils (or of the listed wires) [J/kg].
        floor_material: the wire whose ``u`` sets the floor.
        arm_moving_mass: the mass of the arm's moving links [kg] (not the ground, no payload).
        bound: ``max_spring_mass`` [kg], or None.
    """

    springs: dict[str, float]
    floor: float
    energy_swing: float
    energy_per_kg: float
    floor_material: str
    arm_moving_mass: float
    bound: float | None = None

    @property
    def total(self) -> float:
        """The springs' total mass [kg]."""
        return float(sum(self.springs.values()))

    @property
    def ratio_to_floor(self) -> float:
        """Total over floor [1] (NaN when the floor is 0: a workspace with no swing of gravity energy)."""
        return self.total / self.floor if self.floor > 0 else float("nan")

    @property
    def ratio_to_arm(self) -> float:
        """Total over the arm's moving mass [1] (NaN for an arm without moving mass)."""
        return self.total / self.arm_moving_mass if self.arm_moving_mass > 0 else float("nan")

    def to_dict(self) -> dict[str, Any]:
        """The record of ``design.json``'s ``spring_mass`` (kg, J, J/kg; a ratio that is NaN is null)."""

        def number(value: float) -> float | None:
            return float(value) if np.isfinite(value) else None

        return {
            "total_kg": self.total,
            "floor_kg": self.floor,
            "ratio_to_floor": number(self.ratio_to_floor),
            "arm_moving_mass_kg": self.arm_moving_mass,
            "ratio_to_arm": number(self.ratio_to_arm),
            "gravity_energy_swing_j": self.energy_swing,
            "energy_per_kg_j": self.energy_per_kg,
            "floor_material": self.floor_material,
            "max_spring_mass_kg": self.bound,
            "springs_kg": dict(self.springs),
        }


def coil_energy_per_kg(material: Material, kind: str, wire_diameter: float, index: float, active_coils: float) -> float:
    r"""``u = (f S_ut(d) / K_B(C))² / (4 G ρ) · n / (n + 2)`` [J/kg]: the most elastic energy a coil of
    ``material`` stores per kilogram of its wire when its Bergsträsser-corrected body stress is the allowable
    ``f S_ut(d)`` of ``kind`` (Shigley Tables 10-4 to 10-7); wire diameter ``d`` [m], index ``C`` [1],
    ``n`` active coils of ``n + 2`` (the ends store nothing)."""
    allowable = float(material.allowable_stress(wire_diameter, kind))  # [Pa]
    nominal = allowable / float(bergstrasser_factor(index))  # largest uncorrected stress 8 F D/(π d³) [Pa]
    return nominal**2 / (4 * material.shear_modulus * material.density) / (1 + 2 / active_coils)  # n/(n + 2)


def fatigue_energy_fraction(material: Material, kind: str, wire_diameter: float, index: float, duty: Duty) -> float:
    r"""The share [1] of a coil's static energy per kilogram that it can exchange while living ``duty``: the
    largest :math:`(F_{max}^2 - F_{min}^2)/F_s^2` over ``0 ≤ F_min ≤ F_max ≤ F_s`` at which every location of
    :func:`~springbalance.springs.fatigue.fatigue_margins` reaches the duty's safety factor, where
    :math:`F_s = \pi d^3 \tau_a/(8 K_B D)` [N] is the force at the body's static allowable stress; wire
    ``d`` [m], index ``C = D/d``. For each ``F_min`` the largest ``F_max`` is found by bisection (the damage grows
    with it), and ``F_min`` by a bounded scalar search. The share depends on these arguments only, so each one is
    searched once per process (a design's report, flags and table ask for it several times)."""
    key = (_material_key(material), kind, float(wire_diameter), float(index), duty)
    if key not in _FRACTIONS:
        _FRACTIONS[key] = _search_fatigue_energy_fraction(material, kind, float(wire_diameter), float(index), duty)
    return _FRACTIONS[key]


#: :func:`fatigue_energy_fraction` of the arguments already searched
_FRACTIONS: dict[tuple, float] = {}


def _material_key(material: Material) -> tuple:
    """The material's values as a hashable key (its fraction tables are dicts)."""
    fields = dataclasses.astuple(material)
    return tuple(tuple(sorted(value.items())) if isinstance(value, dict) else value for value in fields)


def _search_fatigue_energy_fraction(
    material: Material, kind: str, wire_diameter: float, index: float, duty: Duty
) -> float:
    """The search of :func:`fatigue_energy_fraction`."""
    from scipy.optimize import minimize_scalar  # SciPy's optimiser is loaded when a duty's floor is asked for

    mean = index * wire_diameter  # D [m]
    allowable = float(material.allowable_stress(wire_diameter, kind))
    static = np.pi * wire_diameter**3 * allowable / (8 * float(bergstrasser_factor(index)) * mean)  # F_s [N]

    def lives(low: float, high: float) -> bool:
        margins = fatigue_margins(wire_diameter, mean, material, low, high, duty, kind).values()
        return all(margin.safety_factor >= margin.required for margin in margins)

    def largest_high(low: float) -> float:
        if not lives(low, low):
            return low  # a steady force this large already fails: no swing
        if lives(low, static):
            return static
        below, above = low, static
        for _ in range(40):
            middle = 0.5 * (below + above)
            below, above = (middle, above) if lives(low, middle) else (below, middle)
        return below

    def swing(fraction: float) -> float:
        low = fraction * static
        return -((largest_high(low) ** 2 - low**2) / static**2)

    best = minimize_scalar(swing, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-6})
    return float(max(-best.fun, -swing(0.0)))


def _limits(spring: HelicalCoilSpring, key: str) -> tuple[float, float]:
    value = spring.parameters[key]
    if isinstance(value, Free):
        return float(np.min(value.lower)), float(np.max(value.upper))
    return float(value), float(value)


def best_energy_per_kg(spring: HelicalCoilSpring) -> float:
    """The largest ``u`` [J/kg] of :func:`coil_energy_per_kg` that ``spring``'s bounds allow: its thinnest wire,
    its largest index (within ``index_range`` for a coil to be wound) and its most active coils; for a coil with
    a ``duty``, times :func:`fatigue_energy_fraction` there."""
    thinnest = _limits(spring, "wire_diameter")[0]
    widest = _limits(spring, "mean_diameter")[1]
    index = widest / thinnest
    if spring.winds:
        index = min(index, spring.index_range[1])
    coils = _limits(spring, "active_coils")[1]
    energy = coil_energy_per_kg(spring.material, spring.helical_kind, thinnest, index, coils)
    if spring.duty is None:
        return energy
    return energy * fatigue_energy_fraction(spring.material, spring.helical_kind, thinnest, index, spring.duty)


def listed_energy_per_kg() -> tuple[float, str]:
    """``(u, material)``: the largest ``u`` [J/kg] of the listed wires, each at its thinnest wire, index
    :data:`DEFAULT_INDEX` and ``n/(n + 2) → 1``, over both kinds (the floor of a design without coils)."""
    best = max(
        (coil_energy_per_kg(material, kind, material.diameter_range[0], DEFAULT_INDEX, np.inf), name)
        for name, material in MATERIALS.items()
        for kind in KINDS
    )
    return best[0], best[1]


def gravity_energy_swing(workspace: Workspace, blocks: int = 1) -> float:
    """``ΔV = max_q V_g(q) − min_q V_g(q)`` [J] of the unbalanced arm over the samples of ``workspace``, the
    largest over its ``blocks`` scenario blocks (each load case is balanced on its own)."""
    potential = workspace.kinematics().potential.reshape(blocks, -1)
    return float(np.max(np.ptp(potential, axis=1))) if potential.size else 0.0


def part_masses(springs: Sequence[Spring], values: Mapping[str, Mapping[str, Any]]) -> dict[str, float]:
    """Each spring's part mass [kg] at its parameter values (``values``: spring name → values)."""
    return {str(spring.name): float(spring.part_mass(dict(values[str(spring.name)]))) for spring in springs}


def spring_mass(problem: _Problem, x: np.ndarray) -> SpringMass:
    """The spring-mass record of design ``x`` of ``problem`` (scenario 0's values of per-scenario variables)."""
    values = {str(spring.name): problem.model.spring_values(spring, x) for spring in problem.springs}
    coils = [spring for spring in problem.springs if isinstance(spring, HelicalCoilSpring)]
    if coils:
        energy, material = max((best_energy_per_kg(coil), coil.material.name) for coil in coils)
    else:
        energy, material = listed_energy_per_kg()
    scenarios = getattr(problem, "scenarios", None) or ()
    swing = gravity_energy_swing(problem.workspace, max(len(scenarios), 1))
    return SpringMass(
        part_masses(problem.springs, values),
        swing / energy,
        swing,
        energy,
        material,
        float(problem.mechanism.summary()["moving_mass"]),
        problem.max_spring_mass,
    )


def lightest_values(spring: Spring) -> dict[str, float]:
    """Every parameter of ``spring`` at its lower bound (a fixed one at its value): where a part's mass is least
    (a coil's mass grows with ``d``, ``D`` and ``n``, a coupled mass with the stiffness)."""
    return {
        key: float(np.min(value.lower)) if isinstance(value, Free) else float(value)
        for key, value in spring.parameters.items()
    }


def check_mass_bound(problem: _Problem) -> None:
    """Raise :class:`InputError` when ``max_spring_mass`` is below the mass of the lightest springs that the
    bounds allow (every spring's parameters at their lower bounds); nothing without a bound."""
    bound = problem.max_spring_mass
    if bound is None:
        return
    masses = part_masses(problem.springs, {str(s.name): lightest_values(s) for s in problem.springs})
    lightest = sum(masses.values())
    if lightest > bound * (1 + 1e-9):
        parts = ", ".join(f"{name} {mass:.4g} kg" for name, mass in masses.items() if mass > 0)
        raise InputError(
            f"max_spring_mass {bound:g} kg is below the lightest springs the bounds allow, {lightest:.4g} kg "
            f"({parts}): raise max_spring_mass or lower the wire, coil diameter or coil bounds"
        )
