"""The manufacturing tolerances an order states, per quality grade (EN 15800, DIN 2097).

A spring order gives every inspected value with its ± tolerance: the free length ``L0``, the controlled coil
diameter, the initial tension ``F0`` (extension springs), the rate ``R`` and the loads ``F1``, ``F2`` at
the test lengths. They follow from the quality grade (DIN 2097 for extension springs, EN 15800 for
compression springs; grades 1, 2, 3, grade 2 by default) and the spring's geometry.

:func:`grade_tolerances` computes them with :mod:`springbalance.springs.tolerance_grades` (EN 15800:2008 §4
and DIN 2097): ``A_F`` on each load, ``A_L0`` on the free length, ``A_D`` on the coil diameter, ``A_F(F0)``
on the initial tension, and the proportional part ``1.5 % Q`` of ``A_F`` on the rate.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from springbalance.springs.tolerance_grades import (
    DEFAULT_GRADE,
    Kind,
    force_tolerance,
    grade_box,
    initial_tension_tolerance,
)

__all__ = ["DEFAULT_GRADE", "GRADES", "GRADE_STANDARDS", "Tolerances", "grade_tolerances"]
#: the quality grades of DIN 2097 and EN 15800 (1 fine, 2 medium: the default, 3 coarse)
GRADES = (1, 2, 3)
#: the standard of the tolerances per spring kind
GRADE_STANDARDS = {"extension": "DIN 2097", "compression": "EN 15800"}


@dataclasses.dataclass(frozen=True)
class Tolerances:
    """The ± tolerances of one spring at one quality grade (SI units; None: not available, see ``missing``).

    Attributes:
        grade: the quality grade (1, 2 or 3).
        standard: "DIN 2097" (extension) or "EN 15800" (compression).
        free_length: ± on ``L0`` [m].
        coil_diameter: ± on the controlled coil diameter [m].
        initial_tension: ± on ``F0`` [N] (extension springs).
        rate: ± on the rate [N/m].
        loads: ± on ``F1`` and ``F2`` [N].
        source: where the numbers come from.
        missing: why a value is None ("" when every value is given).
    """

    grade: int
    standard: str
    free_length: float | None = None
    coil_diameter: float | None = None
    initial_tension: float | None = None
    rate: float | None = None
    loads: tuple[float | None, float | None] = (None, None)
    source: str = ""
    missing: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The record of ``order.json`` (``loads`` as a list)."""
        record = dataclasses.asdict(self)
        record["loads"] = list(self.loads)
        return record


def grade_tolerances(
    kind: str,
    grade: int,
    wire_diameter: float,
    mean_diameter: float,
    active_coils: float,
    free_length: float,
    rate: float,
    initial_tension: float,
    loads: tuple[float, float],
) -> Tolerances:
    """The tolerances of a ``kind`` ("extension" or "compression") spring of quality ``grade`` with wire
    ``wire_diameter`` d [m], mean coil diameter ``mean_diameter`` D [m], ``active_coils`` n, free length
    ``free_length`` L0 [m], rate [N/m], initial tension [N] and working loads ``loads`` (F1, F2) [N]
    (:mod:`springbalance.springs.tolerance_grades`; an extension spring's initial tension is toleranced as
    the force at its free length, a compression spring has none: its ``initial_tension`` is None)."""
    d, D, n = wire_diameter, mean_diameter, active_coils
    force_kind: Kind = "extension" if kind == "extension" else "compression"
    box = grade_box(force_kind, d, D, n, free_length, rate, initial_tension, grade)
    return Tolerances(
        grade=grade,
        standard=GRADE_STANDARDS[kind],
        free_length=box.free_length_dimension,
        coil_diameter=box.coil_diameter,
        initial_tension=initial_tension_tolerance(d, D, n, initial_tension, grade) if kind == "extension" else None,
        rate=box.rate * rate,
        loads=(force_tolerance(d, D, n, loads[0], grade), force_tolerance(d, D, n, loads[1], grade)),
        source=f"{GRADE_STANDARDS[kind]} grade {grade} (springbalance.springs.tolerance_grades)",
    )
