"""One task of a study: one spring topology at one grid point, solved by a pure function of its payload.

A :class:`Task` carries the full design config of its topology (``record``: the study's config
with the topology's springs and the grid point's overrides). :func:`task_payload` turns it into
the plain mapping that travels to a worker, and :func:`solve_task` solves it there (the
multi-start of one design problem), so the same task gives the same result on any worker.
A design balances exactly when its peak residual torque is below :data:`EXACT` times the
unbalanced peak [1].
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from springbalance.design.torque_model import one_thread
from springbalance.errors import SolverError, SpringBalanceError
from springbalance.io.config import config_from_dict
from springbalance.pipeline import solve

if TYPE_CHECKING:
    from springbalance.results.result import DesignResult

#: a design balances exactly when its residual peak is below this fraction of the unbalanced peak
EXACT = 1e-6


@dataclasses.dataclass
class Task:
    """One topology at one grid point: ``record`` is the full design config given to :func:`solve_task`."""

    id: str
    topology: tuple[int, ...]
    labels: tuple[str, ...]
    grid: dict[str, Any]
    record: dict[str, Any]
    #: why pruning skipped this topology ("" for a topology solved for exact balance): a pruned one is
    #: solved only for its spring count's best approximate design (:mod:`springbalance.explore.approximate`)
    pruned: str = ""

    @property
    def count(self) -> int:
        """The number of springs of the topology."""
        return len(self.topology)


def task_payload(
    task: Task, base_dir: Path, starts: int, seed: int, seeds: Sequence[int] | None = None
) -> dict[str, Any]:
    """The mapping :func:`solve_task` takes: the task's record, the folder its relative paths start from,
    and the multi-start's ``starts`` and ``seed`` (or ``seeds``: solved at each, the best design kept)."""
    return {
        "id": task.id,
        "labels": list(task.labels),
        "grid": task.grid,
        "record": task.record,
        "base_dir": str(base_dir),
        "starts": starts,
        "seed": seed,
        **({"seeds": list(seeds)} if seeds is not None else {}),
        "pruned": task.pruned,
    }


def solve_task(payload: dict[str, Any]) -> dict[str, Any]:
    """Solve one task (a pure function of ``payload``): the multi-start of one topology at one grid point.

    Returns the row of ``results.csv`` plus ``design``, the design's saved record (None when it failed).
    """
    clock = time.perf_counter()
    row: dict[str, Any] = {
        "id": payload["id"],
        "springs": payload["labels"],
        "count": len(payload["labels"]),
        "grid": payload["grid"],
        "starts": payload["starts"],
        "seed": payload["seed"],
        "pruned": payload.get("pruned", ""),
    }
    try:
        config = config_from_dict(payload["record"], payload["base_dir"], f"task {payload['id']}")
        # one process and one thread per task: the study spreads tasks over the cores, not the starts of one task
        with one_thread():
            seeds = payload.get("seeds")  # solved at each, the best kept (the row's seed: the kept one)
            seed = None if seeds else payload["seed"]
            result = solve(config, starts=payload["starts"], seed=seed, seeds=seeds, progress=False, workers=1)
    except (SolverError, SpringBalanceError) as error:
        message = str(error).splitlines()[0]
    except (
        ArithmeticError,
        ValueError,
        RuntimeError,
    ) as error:  # numerical trouble: this topology fails, not the study
        message = f"{type(error).__name__}: {str(error).splitlines()[0]}"
    else:
        kept = {"seed": result.seed} if payload.get("seeds") else {}
        return {**row, **kept, **_solved_row(result), "seconds": time.perf_counter() - clock}
    failed = {"status": "failed", "error": message, "exact": False, "ok": False, "failures": [], "design": None}
    return {**row, **failed, "seconds": time.perf_counter() - clock}


def _solved_row(result: DesignResult) -> dict[str, Any]:
    """The columns of a solved task: objective before and after, residual (relative to the unbalanced
    peak), exactness, the springs' total mass [kg], whether every spring is buildable, and whether the design
    passes every check (``ok``; else ``failures``, the kinds of its failures, sorted, once each)."""
    metrics = result.metrics()
    balance = result.exact_balance()
    objective = metrics["optimised"]
    masses = [record.get("mass") for record in result.springs]
    known = [mass for mass in masses if mass is not None]
    sheets = [record["helical"]["buildable"] for record in result.springs if isinstance(record.get("helical"), dict)]
    findings = result.warnings()
    flags = [flag.kind for flag in findings]
    failures = sorted({flag.kind for flag in findings if flag.failure})
    # buildable: every spring is a coil whose spec sheet passes (an ideal law, such as a zero-free-length
    # spring, says nothing about a part that could be wound)
    buildable = (
        len(sheets) == len(result.springs)
        and all(sheets)
        and not any(kind in ("unbuildable", "unbuildable_ideal") for kind in flags)
    )
    return {
        "status": "solved",
        "objective": objective,
        "objective_value": metrics["objectives"][objective]["after"],
        "objective_before": metrics["objectives"][objective]["before"],
        "peak_residual": balance["residual"],
        "relative_residual": balance["relative_residual"],
        "exact": bool(balance["relative_residual"] < EXACT),
        "spring_mass": float(sum(known)) if masses and len(known) == len(masses) else None,
        "buildable": bool(buildable),
        "ok": not failures,
        "failures": failures,
        "error": "",
        "design": result.to_dict(),
    }
