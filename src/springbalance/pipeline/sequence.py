"""The solve sequence, run once: :data:`~springbalance.pipeline.steps.STEPS` from a problem to a design."""

from __future__ import annotations

import numpy as np

from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import workers_default
from springbalance.model import budget
from springbalance.pipeline.state import SolveOptions, SolveState
from springbalance.pipeline.steps import STEPS
from springbalance.results.result import DesignResult


def run_steps(problem: DesignProblem, options: SolveOptions) -> DesignResult:
    """Every step in order, with ``options.workers`` as the default of every solve along the way and the polish
    budget the problem needs (:meth:`SolveOptions.for_problem`); the
    design of the last state as a :class:`DesignResult` (of the problem with the final linear rows)."""
    _check_starts(problem, options.starts)
    options = options.for_problem(problem)
    with workers_default(options.workers):
        state = SolveState(problem, options)
        for step in STEPS:
            state = step(state)
    solution = state.solved
    return DesignResult(
        state.problem,
        solution.x,
        starts=solution.starts,
        method=solution.method,
        seed=solution.seed,
        status=solution.status,
        wire_rounding=state.wire_rounding,
        joint_hold=state.joint_hold,
        fit=state.fit,
        verification=state.verification,
        twin=state.twin,
    )


def _check_starts(problem: DesignProblem, starts: object) -> None:
    """The start points must fit the memory budget (a bad count is the solver's error, named there)."""
    if isinstance(starts, (int, np.integer)) and not isinstance(starts, bool) and starts > 0:
        budget.require(
            budget.FLOAT * 4 * int(starts) * max(problem.variables.size, 1),
            f"{starts} starts of {problem.variables.size} design variables",
        )
