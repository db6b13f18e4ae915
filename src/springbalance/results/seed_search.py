"""A design solved at several seeds, the best kept: what each seed gave (``springbalance.solve(..., seeds=[...])``).

A fit to the arm is a chain of local solves, and where it ends depends on where it starts: the same problem at
another seed of its start points may end several points of RMS cut higher or lower, or fail a check
(docs/guides/clearance.md). Solving at a few seeds and keeping the best design that passes its checks is the
remedy the guide gives; ``seeds`` does it in one call. The design kept is, of the seeds' designs, the first by

1. passing every check (no failure of :meth:`~springbalance.results.result.DesignResult.failures`),
2. fewest failures,
3. lowest objective (in the objective's unit), then the seed listed first;

a seed whose solve found no feasible design at all (``SolverError``) is never kept. :class:`SeedSearch` records
every seed's outcome; ``design.json`` keeps it under ``solver.seeds`` and the text report prints it.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Sequence


@dataclasses.dataclass(frozen=True)
class SeedRun:
    """What the solve at one seed gave.

    Attributes:
        seed: the seed of the start points.
        objective: the design's objective [the objective's unit], or None when the solve found no design.
        failures: the kinds of the design's failures (``overlap``, ``worse_joint``, ...; empty when it passes).
        seconds: the solve's wall time [s].
        error: why the solve found no design (its ``SolverError``), or None.
    """

    seed: int
    objective: float | None
    failures: tuple[str, ...] = ()
    seconds: float = 0.0
    error: str | None = None

    @property
    def ok(self) -> bool:
        """Whether the seed's design exists and passes every check."""
        return self.objective is not None and not self.failures

    def rank(self) -> tuple[bool, int, float]:
        """The order of :func:`best_run` (lower is better): failing, failure count, objective."""
        objective = math.inf if self.objective is None else self.objective
        return (not self.ok, len(self.failures), objective)

    def to_dict(self) -> dict[str, Any]:
        record: dict[str, Any] = {
            "seed": self.seed,
            "objective": self.objective,
            "failures": list(self.failures),
            "seconds": self.seconds,
        }
        return {**record, "error": self.error} if self.error is not None else record

    @classmethod
    def from_dict(cls, record: Any) -> SeedRun:
        objective = record.get("objective")
        return cls(
            int(record["seed"]),
            None if objective is None else float(objective),
            tuple(str(kind) for kind in record.get("failures", [])),
            float(record.get("seconds", 0.0)),
            None if record.get("error") is None else str(record["error"]),
        )


def best_run(runs: Sequence[SeedRun]) -> SeedRun | None:
    """The run whose design is kept (see the module documentation), or None when no seed found a design."""
    found = [run for run in runs if run.objective is not None]
    return min(found, key=SeedRun.rank) if found else None  # min keeps the first of equals


@dataclasses.dataclass(frozen=True)
class SeedSearch:
    """Every seed's outcome and the seed whose design was kept.

    Attributes:
        runs: one :class:`SeedRun` per seed, in the order they were solved.
        kept: the seed whose design is the result.
    """

    runs: tuple[SeedRun, ...]
    kept: int

    @property
    def seconds(self) -> float:
        """The wall time of all the seeds' solves [s]."""
        return float(sum(run.seconds for run in self.runs))

    def lines(self, unit: str) -> list[str]:
        """The text report's lines: which seed was kept, then each seed's objective [``unit``] and outcome."""
        seeds = ", ".join(str(run.seed) for run in self.runs)
        lines = [f"  solved at seeds {seeds} ({self.seconds:.1f} s); kept the design of seed {self.kept}:"]
        for run in self.runs:
            if run.objective is None:
                outcome = f"no design ({run.error})"
            else:
                outcome = f"{run.objective:.6g} {unit}, " + (", ".join(run.failures) if run.failures else "passes")
            lines.append(f"    seed {run.seed}: {outcome}" + ("  ← kept" if run.seed == self.kept else ""))
        return lines

    def summary(self, unit: str) -> str:
        """One sentence for report.html: the seeds, the one kept, and each seed's objective [``unit``] and failures."""
        outcomes = "; ".join(
            f"{run.seed}: "
            + ("no design" if run.objective is None else f"{run.objective:.4g} {unit}")
            + "".join(f", {kind}" for kind in run.failures)
            for run in self.runs
        )
        return f"Solved at {len(self.runs)} seeds, the design of seed {self.kept} kept ({outcomes})."

    def to_dict(self) -> dict[str, Any]:
        """The record in ``design.json`` (``solver.seeds``)."""
        return {"kept": self.kept, "runs": [run.to_dict() for run in self.runs]}

    @classmethod
    def from_dict(cls, record: Any) -> SeedSearch | None:
        """The record a saved design carries (None when it has none or it is damaged)."""
        if not isinstance(record, dict):
            return None
        try:
            runs = tuple(SeedRun.from_dict(run) for run in record["runs"])
            return cls(runs, int(record["kept"]))
        except (KeyError, TypeError, ValueError, AttributeError):
            return None
