"""The manufacturing tolerances an order states, per quality grade (the seam to the tolerance tables).

A spring order gives every inspected value with its ± tolerance: the free length ``L0``, the controlled coil
diameter, the initial tension ``F0`` (extension springs), the rate ``R`` and the loads ``F1``, ``F2`` at
the test lengths. They follow from the quality grade (DIN 2097 for extension springs, EN 15800 for
compression springs; grades 1, 2, 3, grade 2 by default) and the spring's geometry.

:func:`grade_tolerances` is the one function that computes them. The grade tables are not part of this
build (issue 28 part 3 adds them as ``springbalance.springs.tolerance_grades``): until they are, it returns
a :class:`Tolerances` whose values are None and whose ``missing`` says why, and the order prints that
reason in every tolerance cell instead of a number.
"""

from __future__ import annotations

import dataclasses
from typing import Any

#: the quality grade an order asks for when the design gives none (DIN 2097 / EN 15800: 1 fine, 2 medium,
#: 3 coarse; 2 is the usual grade of a spring made to order)
DEFAULT_GRADE = 2
#: the quality grades of DIN 2097 and EN 15800
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
    ``free_length`` L0 [m], rate [N/m], initial tension [N] and working loads ``loads`` (F1, F2) [N].

    The grade tables (DIN 2097, EN 15800) are not in this build: the values are None, and ``missing``
    says so; nothing is guessed.
    """
    return Tolerances(
        grade=grade,
        standard=GRADE_STANDARDS[kind],
        missing=f"the {GRADE_STANDARDS[kind]} grade {grade} tables are not in this build of springbalance "
        "(issue 28, tolerances); take the standard's tolerances for this grade",
    )
