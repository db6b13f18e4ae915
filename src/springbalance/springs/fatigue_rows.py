r"""Fatigue as a constraint of the optimisation (docs/model.md §3.8.2): the rows of a coil with a ``duty``.

The force range over the workspace is not known before the solve, so each coil with a duty has one
auxiliary design variable, a lower bound ``F_lo`` [N] of its force magnitude ``P`` (tension of an
extension spring, push of a compression spring), and at every sample ``i`` the rows

.. math::
    P_i - F_{lo} \ge 0, \qquad
    r\bigl(\tau_a = c\,(P_i - F_{lo})/2,\ \tau_m = c\,(P_i + F_{lo})/2\bigr) \ge 0

per location (:func:`~springbalance.springs.fatigue.damage_row`, ``c`` the stress per newton). The row ``r``
falls as ``P_i`` grows, so the rows at every sample hold iff they hold at ``max_i P_i``; and it rises with
``F_lo`` (Goodman always; Gerber while :math:`2 n \tau_m S_e < S_u^2`, which the static stress rule keeps for
every wire of the catalogue but the peened Zimmerli point on wire weaker than 1200 MPa), so the best
``F_lo`` is ``min_i P_i``: the rows are exact, ``n_f(F_min, F_max) ≥ n`` at the solution.
"""

from __future__ import annotations

import math
from typing import Any

from springbalance.springs.fatigue import (
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


class FatigueRules:
    """The fatigue rows of a helical coil ``spring`` (it has ``material``, ``helical_kind``, ``duty``,
    ``stress_reserve`` and wire and coil parameters) at one sample, ``≥ 0`` when the rule holds."""

    name = "fatigue"

    def __init__(self, spring: Any, duty: Duty):
        self.spring, self.duty = spring, duty
        self.kind = spring.helical_kind
        largest = self.largest_force()
        self.parts = (("fatigue_floor", "N", max(0.01 * largest, 1e-3)),) + tuple(
            (f"fatigue_{location}", "1", 0.1) for location in LOCATIONS[self.kind]
        )
        #: the damage rows keep ``stress_reserve`` in reserve [1]
        self.reserves = {f"fatigue_{location}": spring.stress_reserve for location in LOCATIONS[self.kind]}
        #: the auxiliary variable ``F_lo`` [N]: (name, unit, lower, upper, start)
        self.auxiliary = ((FLOOR, "N", 0.0, largest, 0.0),)

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
        spring, duty = self.spring, self.duty
        d, D = parameters["wire_diameter"], parameters["mean_diameter"]
        load = force if self.kind == "extension" else -force  # P [N]
        floor = parameters[FLOOR]  # F_lo [N]
        factor = RELIABILITY[duty.reliability]
        rows = [load - floor]
        for location in LOCATIONS[self.kind]:
            c = stress_per_force(location, d, D)  # [Pa/N]
            point = fatigue_point(spring.material, d, location, duty.cycles, duty.peened)
            amplitude, mean = 0.5 * c * (load - floor), 0.5 * c * (load + floor)
            row = damage_row(amplitude, mean, point, duty.criterion, duty.safety_factor, factor)
            rows.append(row - spring.stress_reserve)
        return rows
