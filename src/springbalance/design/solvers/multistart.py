"""The multi-start with polish: every start runs with the iteration budget, then the starts close to the best
that the budget stopped go on ("screen, then polish"); the best feasible start wins (:func:`solve_problem`).

One start (:meth:`_MultiStartSolver.run`) is cold (least squares, then IPOPT when needed) or warm (from
IPOPT's multipliers of a nearby problem's solution, :meth:`_MultiStartSolver._warm`).
"""

from __future__ import annotations

import sys
import time
from typing import Sequence

import numpy as np
from threadpoolctl import threadpool_limits

from springbalance.design.evaluation import Evaluation
from springbalance.design.solvers.floors import lowered_floors
from springbalance.design.solvers.ipopt import IpoptStarts
from springbalance.design.solvers.least_squares import STEP_SIZE_STOP, LeastSquaresStarts
from springbalance.design.solvers.polish import best_record, polished_best
from springbalance.design.solvers.pool import _pool_workers, _StartRunner, check_workers
from springbalance.design.solvers.records import (
    FEASIBILITY_TOLERANCE,
    METHODS,
    Problem,
    Solution,
    StartRecord,
)
from springbalance.design.solvers.starts import start_points
from springbalance.errors import InputError, Interrupted

#: the polish budget when none is given: this many times ``max_iterations`` (:func:`solve_problem`)
POLISH_FACTOR = 4


def solve_problem(
    problem: Problem,
    starts: int = 8,
    seed: int = 0,
    method: str = "auto",
    progress: bool | None = None,
    max_iterations: int = 100,
    tolerance: float = 1e-8,
    polish_iterations: int | None = None,
    *,
    initial: np.ndarray | None = None,
    multipliers: np.ndarray | None = None,
    fixed: Sequence[str] | None = None,
    workers: int | None = None,
    label: str = "starts",
) -> Solution:
    """Run every start and return the best feasible design (see :meth:`DesignProblem.solve`).

    Screen, then polish: every start runs with ``max_iterations``; up to three feasible starts
    within 25 % of the best that stopped on the iteration limit (least squares' or IPOPT's) then
    continue from where they stopped for up to ``polish_iterations`` (default :data:`POLISH_FACTOR` × max_iterations).
    Starts that stall far from the best cost only their budget, and the chosen design still
    converges. When no start is feasible, up to three that the limit stopped (the least violated)
    continue first.

    ``initial``: the first start (physical units; default the problem's initial guess), or the first
    starts, one per row of a 2-D array (at most ``starts`` rows). ``fixed``: names of design variables
    held at their value in each given start (their bounds collapse to it), so that a problem with some
    variables pinned (a wire at a standard size) is solved without building another; the Sobol starts
    hold them at the first one's. ``multipliers``: IPOPT's multipliers of the NLP rows at ``initial``
    (CasADi's sign, as :attr:`Solution.multipliers`), from a solve of a nearby problem with the same
    rows (a variable held, a bound moved): each given start then goes on from that primal-dual point
    (:meth:`_MultiStartSolver._warm`) instead of starting over. Ignored by ``least_squares`` and when
    the row count differs.

    ``label``: what the progress bar calls the starts.

    ``workers``: processes that run the starts at once (the result does not depend on it); default
    :func:`default_workers` (``os.cpu_count()``), used when a start is expected to last
    :data:`POOL_MIN_SECONDS` (see :class:`_StartRunner`).
    """
    workers = check_workers(workers)
    if method not in METHODS:
        raise InputError(f"unknown solver method {method!r}; valid: {', '.join(METHODS)}")
    starts = int(starts)
    if starts < 1:
        raise InputError(f"starts must be ≥ 1, got {starts}")
    if initial is not None:
        shape = np.shape(initial)
        if (
            len(shape) not in (1, 2)
            or shape[-1] != problem.variables.size
            or (len(shape) == 2 and not 1 <= shape[0] <= starts)
        ):
            raise InputError(
                f"initial must hold {problem.variables.size} design variables, one start or up to "
                f"starts={starts} rows of them; got an array of shape {shape}"
            )
    if method == "least_squares" and not problem.objective.least_squares:
        raise InputError(
            f"method 'least_squares' cannot minimise objective {problem.objective.name!r}; use 'ipopt' or 'auto'"
        )
    # The linear algebra here is small (n ≈ 30 columns): BLAS threads only contend with each
    # other and with the evaluation, badly so on a loaded machine, so use one.
    with threadpool_limits(limits=1, user_api="blas"):
        solver = _MultiStartSolver(problem, method, max_iterations, tolerance, _fixed_mask(problem, fixed))
        runner = _StartRunner(solver, *_pool_workers(problem, workers, starts))
        try:
            return _solve(
                problem,
                runner,
                starts,
                seed,
                method,
                progress,
                max_iterations,
                polish_iterations,
                initial,
                multipliers,
                label,
            )
        finally:
            runner.close()


def _fixed_mask(problem: Problem, names: Sequence[str] | None) -> np.ndarray:
    """The boolean mask of the design variables ``names`` (InputError for a name that is not one)."""
    mask = np.zeros(problem.variables.size, dtype=bool)
    known = {name: index for index, name in enumerate(problem.variables.names)}
    for name in names or ():
        if name not in known:
            raise InputError(f"fixed: {name!r} is not a design variable of this problem")
        mask[known[name]] = True
    return mask


def _solve(
    problem: Problem,
    runner: _StartRunner,
    starts: int,
    seed: int,
    method: str,
    progress: bool | None,
    max_iterations: int,
    polish_iterations: int | None,
    initial: np.ndarray | None = None,
    multipliers: np.ndarray | None = None,
    label: str = "starts",
) -> Solution:
    points = start_points(problem, starts, seed, initial, runner.solver.fixed)
    given = 1 if initial is None else np.atleast_2d(initial).shape[0]
    records = _screen(problem, runner, points, progress, given, multipliers, label)
    polish = POLISH_FACTOR * max_iterations if polish_iterations is None else int(polish_iterations)
    polish = polish if problem.variables.size else 0
    best = polished_best(problem, runner, records, polish, len(points))
    return Solution(best.x, records, method, seed, best.status, best.multipliers)


def _screen(
    problem: Problem,
    runner: _StartRunner,
    points: np.ndarray,
    progress: bool | None,
    given: int,
    multipliers: np.ndarray | None,
    label: str = "starts",
) -> list[StartRecord]:
    """Every start with the screening budget (the ``given`` first ones warm from ``multipliers``), with a
    progress bar (``label``) when asked (default: several starts and a terminal); Ctrl-C raises :class:`Interrupted`
    with the starts that had finished and the best feasible design among them."""
    if progress is None:
        progress = len(points) > 1 and sys.stderr.isatty()
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(points), desc=label, unit="start")
    finished: list[StartRecord] = []

    def done(record: StartRecord) -> None:
        finished.append(record)
        if bar is not None:
            best = min((r.objective for r in finished if r.feasible), default=float("nan"))
            bar.set_postfix(best=f"{best:.4g}")
            bar.update()

    try:
        records = runner.run(
            [(index, points[index], True, multipliers if index < given else None) for index in range(len(points))], done
        )
    except KeyboardInterrupt:
        if bar is not None:
            bar.close()
        feasible = [record for record in finished if record.feasible]
        raise Interrupted(
            f"interrupted: {len(finished)} of {len(points)} starts had finished",
            problem=problem,
            starts=sorted(finished, key=lambda record: record.index),
            total=len(points),
            best_x=best_record(feasible, problem).x if feasible else None,
        ) from None
    if bar is not None:
        bar.close()
    return records


#: the status of a start where the design has no finite value (a spring of zero length: its anchors coincide)
NOT_FINITE = "not run: the design is not finite at this start (a spring of zero length: its two anchors coincide)"


class _MultiStartSolver(LeastSquaresStarts, IpoptStarts):
    """Runs one start at a time (:meth:`run`) of ``problem`` with ``method``: least squares
    (:class:`~springbalance.design.solvers.least_squares.LeastSquaresStarts`), IPOPT
    (:class:`~springbalance.design.solvers.ipopt.IpoptStarts`), or both in turn (``auto``)."""

    def __init__(
        self, problem: Problem, method: str, max_iterations: int, tolerance: float, fixed: np.ndarray | None = None
    ) -> None:
        self.problem = problem
        #: variables held at their start value (bounds collapsed): least squares leaves their columns out
        self.fixed = np.zeros(problem.variables.size, dtype=bool) if fixed is None else np.asarray(fixed, dtype=bool)
        self.method = method
        self.max_iterations = max_iterations
        self.tolerance = tolerance
        self._ls = None
        self._ipopt = None
        self._first = None  # the IPOPT of a lexicographic objective's first phase

    def prepare(self) -> None:
        """Build what every start needs (the compiled least-squares residual and SciPy's least squares,
        the NLP when every start goes to IPOPT), before workers fork. An NLP that only a violated
        constraint calls for is built by the start that needs it."""
        problem = self.problem
        if self.method in ("auto", "least_squares") and problem.variables.size:
            self._residuals()
            import scipy.optimize  # noqa: F401  (0.25 s: imported here once, not by every worker on its own)
        if problem.variables.size and (self.method == "ipopt" or not problem.objective.least_squares):
            self._ipopt_solvers()

    # ------------------------------------------------------------------ one start
    def run(
        self, index: int, z0: np.ndarray, prepare: bool = True, nlp_multipliers: np.ndarray | None = None
    ) -> StartRecord:
        """One start from ``z0`` (scaled); ``prepare``: fit the linear variables and free lengths first.
        ``nlp_multipliers``: IPOPT's multipliers of the NLP rows at ``z0`` (those of a nearby problem's
        solution, or those IPOPT stopped this start with): the start then goes on from that primal-dual
        point (:meth:`_warm`)."""
        problem = self.problem
        clock = time.perf_counter()
        lam_g: np.ndarray | None
        evaluation: Evaluation | None
        z, status, iterations, lam_g, evaluation = np.array(z0, dtype=float), "evaluated", 0, None, None
        if not self.fixed.all() and nlp_multipliers is None:
            start = problem.evaluate(problem.scale(z))
            if not np.isfinite(problem.objective_value(start)):  # no solver can leave a start without a value
                z, status, evaluation = z, NOT_FINITE, start
        if not self.fixed.all() and evaluation is None:
            z, status, iterations, lam_g, evaluation = (
                self._warm(z, nlp_multipliers)
                if nlp_multipliers is not None and self._matches(nlp_multipliers)
                else self._cold(z, prepare)
            )
        if evaluation is None:
            evaluation = problem.evaluate(problem.scale(z))
        evaluation = self._floors_lowered(evaluation)
        tiebreak = problem.objective.tiebreak(
            evaluation.tau * problem.weights, evaluation.potential, problem.path_steps
        )
        violation = self._violation(evaluation)
        return StartRecord(
            index,
            np.asarray(z0),
            evaluation.x,
            problem.objective_value(evaluation),
            violation,
            status,
            iterations,
            time.perf_counter() - clock,
            tiebreak,
            lam_g,
        )

    def _cold(self, z: np.ndarray, prepare: bool) -> tuple[np.ndarray, str, int, np.ndarray | None, Evaluation | None]:
        """Least squares first (``auto``, ``least_squares``), then IPOPT when asked for, for an objective
        without least-squares structure, or for a constraint that least squares left violated.
        Returns ``(z, status, iterations, lam_g, evaluation)`` (``lam_g``: IPOPT's row multipliers, None
        without IPOPT; ``evaluation``: the design ``z`` evaluated, when it was on the way, else None)."""
        problem = self.problem
        status, iterations, multipliers = "evaluated", 0, None
        if self.method in ("auto", "least_squares"):
            z, status, iterations, multipliers = self._least_squares(z, prepare)
        needs_nlp, evaluation = (
            self.method == "ipopt" or (self.method == "auto" and not problem.objective.least_squares),
            None,
        )
        if not needs_nlp and self.method == "auto" and (problem.model.n_constraints or problem.linear_matrix()[1].size):
            evaluation = problem.evaluate(problem.scale(z))  # (only then is the design evaluated here)
            needs_nlp = self._violation(evaluation) > FEASIBILITY_TOLERANCE or self._stalled(status)
        if not needs_nlp:
            return z, status, iterations, None, evaluation
        evaluation = evaluation if evaluation is not None else problem.evaluate(problem.scale(z))
        z, status, more, lam_g = self._ipopt_solve(
            z, evaluation, multipliers=multipliers if problem.objective.least_squares else None
        )
        return z, status, iterations + more, lam_g, None

    def _stalled(self, status: str) -> bool:
        """Whether least squares stopped on its step size (``xtol``, 1e-10) with penalty rows in its residual: its
        trust region shrank to nothing because the Gauss–Newton model of a penalty row ``max(0, λ - μ c)/√μ`` fails
        at the row's kink, not because the design is stationary. IPOPT then finishes the start (a fitting round of
        the UR5's coils, clearance rows active: least squares stopped so at 2.13 N·m, IPOPT from there reached 0.85)."""
        return status == STEP_SIZE_STOP and self._residuals().n_constraint_rows > 0

    def _warm(
        self, z: np.ndarray, lam_g: np.ndarray
    ) -> tuple[np.ndarray, str, int, np.ndarray | None, Evaluation | None]:
        """The start from a primal-dual point: ``z`` with IPOPT's multipliers ``lam_g`` of the NLP rows.

        IPOPT goes on from it, warm, when it alone minimises the objective. A least-squares objective
        (``auto``) first takes a short augmented-Lagrangian run from ``λ = ν/2`` (the multipliers on the
        scaled rows) for a tenth of the budget: where the residual can vanish, Gauss–Newton reaches
        round-off in it; where least squares only crawls along a flat valley, IPOPT finishes, warm from
        where it stopped. Returns what :meth:`_cold` returns."""
        problem = self.problem
        if self.method == "ipopt" or not problem.objective.least_squares:
            return *self._ipopt_solve(z, problem.evaluate(problem.scale(z)), lam_g=lam_g), None
        ls = self._residuals()
        start = 0.5 * problem.scaled_row_multipliers(-lam_g, ls.n_constraint_rows - ls.n_sample_rows)
        z, status, iterations, multipliers = self._least_squares(z, False, start, max(10, self.max_iterations // 10))
        evaluation = problem.evaluate(problem.scale(z))
        if "iteration limit" not in status and self._violation(evaluation) <= FEASIBILITY_TOLERANCE:
            return z, status, iterations, None, evaluation
        z, status, more, nlp_lam_g = self._ipopt_solve(z, evaluation, multipliers=multipliers)
        return (*self._exact_polish(z, status, iterations + more, nlp_lam_g), None)

    def _floors_lowered(self, evaluation: Evaluation) -> Evaluation:
        """``evaluation``, or the design with its coils' fatigue floors lowered to their least forces
        (:func:`~springbalance.design.solvers.floors.lowered_floors`) when that is less violated: only a start
        that ends outside the rows is touched."""
        if self._violation(evaluation) <= FEASIBILITY_TOLERANCE:
            return evaluation
        lowered = lowered_floors(self.problem, evaluation)
        if lowered is None:
            return evaluation
        trial = self.problem.evaluate(lowered)
        return trial if self._violation(trial) < self._violation(evaluation) else evaluation

    def _violation(self, evaluation: Evaluation) -> float:
        """The largest violation of a constraint row or a linear row [m or N] of an evaluated design."""
        return max(evaluation.max_violation, self.problem.linear_violation(evaluation.x))

    def _matches(self, lam_g: np.ndarray | None) -> bool:
        """Whether a start may begin from IPOPT's multipliers ``lam_g``: a method that runs IPOPT, a
        one-phase objective, constraint rows when least squares comes first, and an NLP of as many rows."""
        problem = self.problem
        if lam_g is None or self.method == "least_squares" or problem.objective.first_phase is not None:
            return False
        if problem.objective.least_squares and self.method == "auto" and not self._residuals().n_constraint_rows:
            return False
        solver, _ = self._ipopt_solvers()
        return np.size(lam_g) == solver.nlp.n_rows
