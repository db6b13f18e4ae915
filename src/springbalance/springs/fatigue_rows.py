r"""Fatigue as a constraint of the optimisation (docs/model.md §3.8.2): the rows of a coil with a ``duty``.

The force range over the workspace is not known before the solve, so each coil with a duty has two
auxiliary design variables, a lower bound ``F_lo`` and an upper bound ``F_hi`` [N] of its force magnitude
``P`` (tension of an extension spring, push of a compression spring): at every sample ``i`` the two rows

.. math::
    P_i - F_{lo} \ge 0, \qquad F_{hi} - P_i \ge 0

(linear in ``P_i``), and once per coil, per location, the damage row
(:func:`~springbalance.springs.fatigue.damage_row`, ``c`` the stress per newton)

.. math::
    r\bigl(\tau_a = c\,(F_{hi} - F_{lo})/2,\ \tau_m = c\,(F_{hi} + F_{lo})/2\bigr) \ge 0 ,

which depends on the wire, the coil and the two bounds only, not on the sample. The row ``r`` falls as
``F_hi`` grows, so the best ``F_hi`` is ``max_i P_i``; and it rises with ``F_lo`` (Goodman always; Gerber
while :math:`2 n \tau_m S_e < S_u^2`, which the static stress rule keeps for every wire of the catalogue but
the peened Zimmerli point on wire weaker than 1200 MPa), so the best ``F_lo`` is ``min_i P_i``: the rows are
exact, ``n_f(F_min, F_max) ≥ n`` at the solution. They admit the same designs as the rows
``r(c (P_i - F_lo)/2, c (P_i + F_lo)/2) ≥ 0`` at every sample (``r`` falls with ``P_i``, so those hold at
every sample iff they hold at ``max_i P_i``), with 2 rows per sample instead of 4 (extension) and damage rows
that the solver differentiates in four variables (``d``, ``D``, ``F_lo``, ``F_hi``) once, instead of in every
variable the force depends on at every sample.
"""

from __future__ import annotations

import math
from typing import Any

from springbalance.springs.fatigue import (
    CEILING,
    FLOOR,
    LOCATIONS,
    RELIABILITY,
    Duty,
    damage_row,
    fatigue_point,
    stress_per_force,
)
from springbalance.springs.helical_formulas import bergstrasser_factor
from springbalance.springs.params import Free
from springbalance.springs.values import Parameters, ValueT

#: the names of the rows of the force bounds (per sample) and of the damage rows (per location, once)
FLOOR_ROW, CEILING_ROW = "fatigue_floor", "fatigue_ceiling"


def damage_part(location: str) -> str:
    """The name of the damage row of ``location`` (``fatigue_body``, ``fatigue_hook_bending`` …)."""
    return f"fatigue_{location}"


class FatigueRules:
    """The fatigue rows of a helical coil ``spring`` (it has ``material``, ``helical_kind``, ``duty``,
    ``stress_reserve`` and wire and coil parameters), ``≥ 0`` when the rule holds: the floor and the ceiling
    of the force at one sample, and the damage row of every location."""

    name = "fatigue"

    def __init__(self, spring: Any, duty: Duty):
        self.spring, self.duty = spring, duty
        self.kind = spring.helical_kind
        largest = self.largest_force()
        force_scale = max(0.01 * largest, 1e-3)
        self.parts = ((FLOOR_ROW, "N", force_scale), (CEILING_ROW, "N", force_scale)) + tuple(
            (damage_part(location), "1", 0.1) for location in LOCATIONS[self.kind]
        )
        #: the damage rows keep ``stress_reserve`` in reserve [1]
        self.reserves = {damage_part(location): spring.stress_reserve for location in LOCATIONS[self.kind]}
        #: the damage rows depend on no sample: the solver evaluates them once, not in every sample's function
        self.once = frozenset(self.reserves)
        #: the bound rows bind at the samples of the smallest and the largest force only
        self.extreme = frozenset((FLOOR_ROW, CEILING_ROW))
        #: the auxiliary variables ``F_lo``, ``F_hi`` [N]: (name, unit, lower, upper, start)
        self.auxiliary = ((FLOOR, "N", 0.0, largest, 0.0), (CEILING, "N", 0.0, largest, largest))

    def largest_force(self) -> float:
        """An upper bound [N] of the force any coil within the bounds carries at its static body allowable:
        ``f S_ut(d) π d²/(8 K_B C)`` at the thickest wire and the smallest index."""
        spring = self.spring
        wire = spring.parameters["wire_diameter"]
        thickest = float(wire.upper) if isinstance(wire, Free) else float(wire)
        index = float(spring.index_range[0])
        strength = spring.material.allowable_fraction[self.kind] * float(spring.material.tensile_strength(thickest))
        return float(strength * math.pi * thickest**2 / (8 * bergstrasser_factor(index) * index))

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> list[ValueT]:
        load = force if self.kind == "extension" else -force  # P [N]
        floor: Any = parameters[FLOOR]  # F_lo [N]
        ceiling: Any = parameters[CEILING]  # F_hi [N]
        return [load - floor, ceiling - load, *self.damage_rows(parameters, floor, ceiling)]

    def damage_rows(self, parameters: Parameters, floor: Any, ceiling: Any) -> list[Any]:
        """The damage row of every location [1] (numbers or CasADi) of a force that cycles between ``floor`` and
        ``ceiling`` [N], less the stress reserve: ``≥ 0`` iff ``n_f`` keeps the required factor with the reserve."""
        spring, duty = self.spring, self.duty
        d, D = parameters["wire_diameter"], parameters["mean_diameter"]
        factor = RELIABILITY[duty.reliability]
        rows = []
        for location in LOCATIONS[self.kind]:
            c = stress_per_force(location, d, D)  # [Pa/N]
            point = fatigue_point(spring.material, d, location, duty.cycles, duty.peened)
            amplitude, mean = 0.5 * c * (ceiling - floor), 0.5 * c * (ceiling + floor)
            row = damage_row(amplitude, mean, point, duty.criterion, duty.safety_factor, factor)
            rows.append(row - spring.stress_reserve)
        return rows
