"""Which designs of the multi-start the clearance loop fits (:func:`fit_from_starts`), side by side.

The loop (:func:`~springbalance.design.clearance_fit.fit_to_arm`) fits the multi-start's best design; whether
the next ranked ones are fitted too depends on how the fits before them ended
(:func:`~springbalance.design.clearance_round.fall_back`). Each fit is a chain of single-start solves, one
core's work, so the fits run on the solve's worker processes, the next one started before its need is known
(:func:`~springbalance.design.solvers.forked.run_in_order`): the same fits, bit for bit, as one after the other.
"""

from __future__ import annotations

import time
from typing import Any, Callable

import numpy as np

from springbalance.design.clearance import FitRecord, LinearRows
from springbalance.design.clearance_fit import fit_to_arm
from springbalance.design.clearance_round import FALLBACK_STARTS, fall_back
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution, forked

#: a fit as a worker returns it: the problem does not pickle, its rows do
Fitted = tuple[Solution, FitRecord, "LinearRows | None"]


def fitted_to_arm(problem: DesignProblem) -> bool:
    """Whether ``problem``'s design is fitted to the arm after its multi-start (:func:`fit_from_starts`): it asks
    for a clearance, or has anchors mounted on the links' surfaces."""
    return problem.clearance is not None or bool(problem.mounts)


def fit_from_starts(
    problem: DesignProblem,
    solution: Solution,
    kept: LinearRows | None = None,
    trusted_first: bool = False,
    tighten: bool = False,
    **solve_options: Any,
) -> tuple[Solution, FitRecord, DesignProblem]:
    """:func:`~springbalance.design.clearance_fit.fit_to_arm` from the :attr:`Clearance.starts` best feasible
    designs of the multi-start (``solution.starts``, distinct, best first); keeps the converged fit of lowest
    objective (else the first). When none converged and a fitting round stopped infeasible, the next ranked
    designs are fitted too, up to :data:`~springbalance.design.clearance_round.FALLBACK_STARTS` more, until one
    converges; when every fit converged only after its rounds moved the design, the next ranked one is fitted
    too (once). ``trusted_first``: each fit's first run has a trust region; ``tighten``: each fitted design is
    tightened (:func:`fit_to_arm`). Returns the fit kept with the problem that carries its rows; its record's
    ``seconds`` are the wall time of all the fits."""
    count = problem.clearance.starts if problem.clearance is not None else 1
    records = sorted((record for record in solution.starts if record.feasible), key=lambda record: record.objective)
    others = [record.x for record in records if not np.array_equal(record.x, solution.x)]

    def fit(x: np.ndarray) -> Callable[[], Fitted]:
        start = Solution(np.array(x, dtype=float), solution.starts, solution.method, solution.seed, solution.status)

        def task() -> Fitted:
            fitted, record, fitted_problem = fit_to_arm(problem, start, kept, trusted_first, tighten, **solve_options)
            return fitted, record, fitted_problem.linear_rows

        return task

    def needed(index: int, done: list[Fitted]) -> bool:
        return index < count or fall_back(done, index - count)

    clock = time.perf_counter()
    tasks = [fit(x) for x in ([solution.x] + others)[: count + FALLBACK_STARTS]]
    fits = [(s, r, problem.with_linear_rows(rows)) for s, r, rows in forked.run_in_order(problem, tasks, needed)]
    converged = [fit for fit in fits if fit[1].converged] or fits[:1]
    fitted, record, fitted_problem = min(converged, key=lambda fit: fit[1].objective)
    record.starts = len(fits)
    if len(fits) > 1:
        record.rounds = sum(fit[1].rounds for fit in fits)
        record.seconds = time.perf_counter() - clock
    return fitted, record, fitted_problem
