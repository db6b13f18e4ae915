"""The polish of a multi-start (:func:`polished_best`): after every start ran with the screening budget, the starts
that the budget stopped go on, those close to the best and those it stopped short of feasible at a lower objective;
the best feasible start wins (:func:`best_record`).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from springbalance.design.solvers.pool import _StartRunner
from springbalance.design.solvers.records import EPIGRAPH_TOLERANCE, Problem, StartRecord
from springbalance.errors import Interrupted, SolverError

#: starts that the budget stopped short of feasible, below the best feasible objective, that the polish continues
PROMISING_INFEASIBLE = 2
#: When no start is feasible, this many of the least violated that the budget stopped are polished; when none is
#: feasible after that polish either, they start again, cold, from where it left them (:func:`polished_best`): least
#: squares first (method ``auto``), which fits the linear variables and the free lengths at once, then IPOPT. The
#: polish goes on warm, with IPOPT's multipliers, and may crawl along the rules: the UR5's four coils (bench_real's
#: ur5-coils, seed 0, an AMD EPYC machine) stopped 5·10⁻⁴-1.5·10⁻³ outside them after 200-317 iterations at every
#: start ("no start gave a feasible design"), and a cold start from the least violated one met them at 0.394 N·m
#: in 0.2 s.
RESTARTS = 3


def polished_best(
    problem: Problem, runner: _StartRunner, records: list[StartRecord], polish: int, total: int
) -> StartRecord:
    """The best feasible start after the polish: when none is feasible, up to :data:`RESTARTS` that the budget
    stopped (the least violated first) go on for ``polish`` iterations, and when none is feasible then, they start
    again, cold, from there; then up to three feasible ones within 25 % of the best that the budget stopped, and up
    to :data:`PROMISING_INFEASIBLE` infeasible ones it stopped at a lower objective than the best, again while they
    close in on the rules (:func:`_polished_again`). :class:`SolverError` when no start is feasible."""
    feasible = [record for record in records if record.feasible]
    for cold in (False, True):
        if feasible or polish <= 0:
            break
        # no start is feasible yet: continue those the budget stopped, the closest to feasible first; when that
        # leaves none feasible either, start them again, cold, from where the polish left them (:data:`RESTARTS`)
        stopped = sorted((r for r in records if _stopped_by_budget(r)), key=lambda record: record.max_violation)
        _polish(runner, problem, records, stopped[:RESTARTS], polish, _less_violated, total, None, cold=cold)
        feasible = [record for record in records if record.feasible]
    if not feasible:
        summary = "; ".join(f"start {r.index}: {r.status}, violation {r.max_violation:.3g}" for r in records)
        raise SolverError(f"no start gave a feasible design ({summary})", problem=problem, starts=records)
    best = best_record(feasible, problem)
    if polish > 0:
        # continue the starts that are close to the best and were stopped by the budget, and those the budget
        # stopped short of feasible at a lower objective than the best (a coil start that IPOPT was still
        # pulling onto its rules must not lose to a feasible start that is no better than no springs)
        near = sorted(
            (r for r in feasible if _stopped_by_budget(r) and r.objective <= 1.25 * best.objective),
            key=lambda record: record.objective,
        )[:3]
        promising = sorted(
            (r for r in records if not r.feasible and _stopped_by_budget(r) and r.objective < best.objective),
            key=lambda record: record.objective,
        )[:PROMISING_INFEASIBLE]
        continued = _polish(runner, problem, records, near + promising, polish, _feasible_and_better, total, best.x)
        best = best_record([r for r in records if r.feasible], problem)
        best = _polished_again(problem, runner, records, promising, continued[len(near) :], polish, total, best)
    return best


#: further polishes of a promising infeasible start that the last one left infeasible, while each cuts its violation ...
REPOLISHES = 2
#: ... to at most this fraction
REPOLISH_PROGRESS = 0.25


def _polished_again(
    problem: Problem,
    runner: _StartRunner,
    records: list[StartRecord],
    candidates: list[StartRecord],
    continued: list[StartRecord],
    polish: int,
    total: int,
    best: StartRecord,
) -> StartRecord:
    """The best feasible start after up to :data:`REPOLISHES` more polishes of the promising infeasible
    ``candidates`` whose polish (``continued``, in their order) stopped on its budget still infeasible but at most
    :data:`REPOLISH_PROGRESS` as violated as before, below the best feasible objective: IPOPT was still closing
    in on the rules (the UR5's four coils at seed 2: two starts polished from 0.038 to 0.0015 at 0.35-0.39 N·m,
    while the only feasible start was the bare arm's 5.2)."""
    for _ in range(REPOLISHES):
        again = [
            new
            for old, new in zip(candidates, continued)
            if not new.feasible
            and _stopped_by_budget(new)
            and new.objective < best.objective
            and new.max_violation <= REPOLISH_PROGRESS * old.max_violation
        ]
        if not again:
            break
        candidates, continued = (
            again,
            _polish(runner, problem, records, again, polish, _feasible_and_better, total, best.x),
        )
        best = best_record([r for r in records if r.feasible], problem)
    return best


def _less_violated(new: StartRecord, old: StartRecord) -> bool:
    """Whether a continued start ``new`` replaces ``old`` while no start is feasible: it breaks its rules less."""
    return new.max_violation < old.max_violation


def _feasible_and_better(new: StartRecord, old: StartRecord) -> bool:
    """Whether a continued start ``new`` replaces ``old``: feasible, and ``old`` was not or had no lower objective."""
    return new.feasible and (not old.feasible or new.objective <= old.objective)


def _stopped_by_budget(record: StartRecord) -> bool:
    """Whether the start stopped on its iteration limit (least squares' or IPOPT's)."""
    return "iteration limit" in record.status or "Maximum_Iterations_Exceeded" in record.status


def _polish(
    runner: _StartRunner,
    problem: Problem,
    records: list[StartRecord],
    candidates: list[StartRecord],
    iterations: int,
    better: Callable[[StartRecord, StartRecord], bool],
    total: int,
    best_x: np.ndarray | None,
    cold: bool = False,
) -> list[StartRecord]:
    """Continue ``candidates`` (starts of ``records``, or their continuations) from where they stopped for up to
    ``iterations``; a continued start replaces the record of its start when ``better(new, old)``. Returns the
    continued starts, in the order of ``candidates``. ``cold``: each starts again from its design as a new start
    would (:data:`RESTARTS`), instead of going on with IPOPT's multipliers."""
    if not candidates:
        return []
    runner.solver.max_iterations = iterations
    try:
        # from where each stopped: its design, and (warm) IPOPT's multipliers when IPOPT stopped it
        continued = runner.run(
            [(r.index, problem.unscale(r.x), cold, None if cold else r.multipliers) for r in candidates]
        )
    except KeyboardInterrupt:
        raise Interrupted(
            f"interrupted while polishing: all {total} starts had finished",
            problem=problem,
            starts=records,
            total=total,
            best_x=best_x,
        ) from None
    position = {record.index: i for i, record in enumerate(records)}
    for record, polished in zip(candidates, continued):
        polished.z0 = record.z0
        polished.status = (
            f"{polished.status} ({'restarted' if cold else 'polished'} after {record.iterations} iterations)"
        )
        polished.iterations += record.iterations
        polished.seconds += record.seconds
        if better(polished, records[position[record.index]]):
            records[position[record.index]] = polished
    return continued


def best_record(records: list[StartRecord], problem: Problem) -> StartRecord:
    """The record of lowest objective; for a lexicographic objective, of those within ``slack`` of
    the lowest, the one of lowest tiebreak."""
    objective = problem.objective
    best = min(records, key=lambda record: record.objective)
    if objective.first_phase is None:
        return best
    window = best.objective * (1.0 + objective.slack) + EPIGRAPH_TOLERANCE * problem.torque_scale
    tied = [r for r in records if r.objective <= window]
    return min(tied, key=lambda record: (record.tiebreak if np.isfinite(record.tiebreak) else np.inf, record.objective))
