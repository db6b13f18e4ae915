"""One fitting round of the clearance loop (:mod:`springbalance.design.clearance_fit`), and what the loop does
when a round stops infeasible.

A round is a warm start of the problem with its linearised rows. When IPOPT stops it infeasible, its
iterate breaks some row (a coil slack, a fatigue bound): the loop may rebuild the rows there and try again,
but it never returns such a design. After :data:`INFEASIBLE_ROUNDS` such rounds in a row, or when the
loop ends on one, it falls back to the last design that met its rows (:func:`fell_back`); that one was
not clear of the arm (else the loop would have stopped there), so the fit is not converged, and
:func:`~springbalance.design.clearance_fit.fit_from_starts` fits the next ranked designs of the
multi-start (:func:`fall_back`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from springbalance.design.clearance import FitRecord
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution, solve_problem
from springbalance.errors import SolverError

#: Fitting rounds in a row that may stop infeasible before the loop gives up on its start.
INFEASIBLE_ROUNDS = 2
#: Designs of the multi-start fitted beyond :attr:`~springbalance.design.clearance.Clearance.starts` when no
#: fit converged and a fitting round stopped infeasible (the next ranked ones, best first).
FALLBACK_STARTS = 2
#: The note a fitting round that stopped infeasible leaves in the solution's status.
INFEASIBLE_NOTE = "a fitting round stopped infeasible"


def solve_round(
    problem: DesignProblem, x: np.ndarray, solution: Solution, solve_options: dict[str, Any]
) -> tuple[Solution | None, str]:
    """One warm start of ``problem`` (with this round's rows) from ``x``, and ``""`` when it met them. When the
    linearised rows cannot all be met from there, the least violating iterate (the next round may rebuild the
    rows there) and the note saying so; None when the solver returned no iterate at all."""
    try:
        return solve_problem(problem, starts=1, initial=x, progress=False, **solve_options), ""
    except SolverError as error:
        if not error.starts:
            return None, ""
        least = min(error.starts, key=lambda record: record.max_violation)
        note = f"{INFEASIBLE_NOTE} ({least.status})"
        return Solution(least.x, solution.starts, solution.method, solution.seed, f"{solution.status}; {note}"), note


def fell_back(
    x: np.ndarray,
    solution: Solution,
    problem: DesignProblem,
    closest: dict[str, float],
    mounts: dict[str, float],
    rounds: int,
    note: str,
) -> tuple[np.ndarray, Solution, DesignProblem, dict[str, float], dict[str, float]]:
    """The last design that met its rows (found after ``rounds`` rounds, with the problem of those rows and
    its check: closest distances [m], mount errors [m]), its status saying a later round stopped (``note``)."""
    status = f"{solution.status}; {note}; fell back to the design of round {rounds}"
    return x, Solution(x, solution.starts, solution.method, solution.seed, status), problem, closest, mounts


def fall_back(fits: list[tuple[Solution, FitRecord, DesignProblem]], extra: int) -> bool:
    """Whether to fit one more (the ``extra``-th beyond ``Clearance.starts``) ranked design: while no fit
    converged, one of them had a fitting round stop infeasible, and fewer than :data:`FALLBACK_STARTS` were
    added."""
    stopped = any(INFEASIBLE_NOTE in fit[0].status for fit in fits)
    return extra < FALLBACK_STARTS and stopped and not any(fit[1].converged for fit in fits)
