"""The tolerance record of a design (docs/model.md §3.10, docs/guides/tolerances.md): a quality grade or
explicit ± on the springs' laws, whether to design for the box (robust) and the adjuster's travel bound.

A config's ``tolerance`` section is read by :meth:`ToleranceSpec.from_record`; bad input gets a one-line
:class:`~springbalance.errors.InputError` naming the key and the value. Units: ``rate`` a fraction of the
rate [1], ``initial_tension`` [N] (the preload of a compression spring), ``free_length`` and
``adjuster_travel`` [m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from springbalance.errors import InputError
from springbalance.springs.tolerance_grades import DEFAULT_GRADE, quality_factor

_KEYS = ("grade", "rate", "initial_tension", "free_length", "robust", "corners", "adjuster_travel")
#: the corner sets of the robust design (docs/model.md §3.10; :mod:`springbalance.design.tolerance_corners`)
CORNERS = ("exact", "strong_weak", "uniform")


@dataclass(frozen=True)
class ToleranceSpec:
    """What the springs may deviate by, and how the design treats it.

    Attributes:
        grade: the quality grade 1, 2, 3 (EN 15800 / DIN 2097) of every coil (default 2), or None when
            the ± are explicit.
        rate: explicit ± on the rate [1, fraction of k], or None.
        initial_tension: explicit ± on the initial tension (extension) or preload (compression) [N], or None.
        free_length: explicit ± on the free length [m], or None.
        robust: design for the box (minimise the worst case over its corners) instead of the nominal law.
        corners: which corners the robust design takes: ``"exact"`` (4 per spring, every combination: the
            worst over the box), ``"strong_weak"`` (each spring strong or weak: the worst peak) or
            ``"uniform"`` (every spring strong, every spring weak).
        adjuster_travel: the adjuster's travel bound [m]: the report says which spring needs more; a robust
            design re-balances each corner with its own settings within it. None: no adjuster.
    """

    grade: int | None = DEFAULT_GRADE
    rate: float | None = None
    initial_tension: float | None = None
    free_length: float | None = None
    robust: bool = False
    adjuster_travel: float | None = None
    corners: str = "exact"

    def __post_init__(self) -> None:
        if self.corners not in CORNERS:
            raise InputError(f"tolerance.corners must be one of {', '.join(CORNERS)}, got {self.corners!r}")
        travel = self.adjuster_travel
        if travel is not None and (isinstance(travel, bool) or not (0 < float(travel) < math.inf)):
            raise InputError(f"tolerance.adjuster_travel must be a positive number [m], got {travel!r}")

    @property
    def explicit(self) -> bool:
        """True when the ± are explicit (they apply to every extension and compression spring)."""
        return self.grade is None

    @classmethod
    def from_record(cls, record: Mapping[str, Any] | None, where: str = "tolerance") -> ToleranceSpec:
        """The spec of a config's ``tolerance`` record: ``{grade}`` or ``{rate, initial_tension, free_length}``
        (any subset, the rest 0), plus ``robust`` and ``adjuster_travel``. One-line InputError naming the key."""
        if record is None:
            return cls()
        if not isinstance(record, Mapping):
            raise InputError(f"{where} must be a mapping, got {record!r}")
        unknown = sorted(set(record) - set(_KEYS))
        if unknown:
            raise InputError(f"{where}: unknown key(s) {', '.join(map(repr, unknown))}; valid: {', '.join(_KEYS)}")
        explicit = {key: record[key] for key in ("rate", "initial_tension", "free_length") if key in record}
        if explicit and record.get("grade") is not None:
            raise InputError(f"{where}: give a grade or explicit ± (rate, initial_tension, free_length), not both")
        values: dict[str, Any] = {}
        for key, value in explicit.items():
            number = _number(value)
            upper = 1.0 if key == "rate" else math.inf
            if not (0 <= number < upper):
                bound = "in [0, 1) [fraction of the rate]" if key == "rate" else "≥ 0 [" + _UNITS[key] + "]"
                raise InputError(f"{where}.{key} must be a number {bound}, got {value!r}")
            values[key] = number
        if explicit:
            values["grade"] = None
        elif "grade" in record:
            try:
                quality_factor(record["grade"])
            except InputError:
                raise InputError(
                    f"{where}.grade must be 1, 2 or 3 (EN 15800 / DIN 2097), got {record['grade']!r}"
                ) from None
            values["grade"] = int(record["grade"])
        robust = record.get("robust", False)
        if not isinstance(robust, bool):
            raise InputError(f"{where}.robust must be true or false, got {robust!r}")
        corners = record.get("corners", "exact")
        if not isinstance(corners, str) or corners not in CORNERS:
            raise InputError(f"{where}.corners must be one of {', '.join(CORNERS)}, got {corners!r}")
        if "corners" in record and not robust:
            raise InputError(f"{where}.corners: {corners!r} needs robust: true (the corners of the robust design)")
        travel = record.get("adjuster_travel")
        if travel is not None:
            number = _number(travel)
            if not (number > 0 and math.isfinite(number)):
                raise InputError(f"{where}.adjuster_travel must be a positive number [m], got {travel!r}")
            travel = number
        return cls(robust=robust, adjuster_travel=travel, corners=corners, **values)

    def to_dict(self) -> dict[str, Any]:
        """The record :meth:`from_record` reads."""
        record: dict[str, Any] = (
            {"grade": self.grade}
            if not self.explicit
            else {key: getattr(self, key) or 0.0 for key in ("rate", "initial_tension", "free_length")}
        )
        if self.robust:
            record["robust"] = True
            if self.corners != "exact":
                record["corners"] = self.corners
        if self.adjuster_travel is not None:
            record["adjuster_travel"] = self.adjuster_travel
        return record


_UNITS = {"initial_tension": "N", "free_length": "m"}


def _number(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return math.nan
    return float(value)
