r"""Solvers for a :class:`~springbalance.design.problem.DesignProblem`, with multi-start.

Backends:

- ``least_squares``: for objectives with least-squares structure (``rms``,
  ``pe_variance``) one per-sample CasADi function of the scaled variables gives the residual
  rows and their exact Jacobian; compiled to C when a compiler is available (the library is
  cached on disk, :mod:`~springbalance.design.compile_cache`) and evaluated over blocks of
  samples straight into NumPy buffers, where ``JᵀJ`` and ``Jᵀr`` are summed. SciPy's bounded
  trust-region-reflective method then works on an equivalent *compressed* residual of n+1
  rows (n ≈ 30 variables, while the residual has N·nv ≈ 25,000 rows), see
  :meth:`_MultiStartSolver._trust_region`. Practical constraints (tension, stretch, force,
  length) enter through an augmented Lagrangian: penalty rows ``max(0, λ - μ c)/√μ`` join
  the residual and the multipliers are updated between runs.
- ``ipopt``: the general NLP of :meth:`DesignProblem.build` with exact derivatives from
  CasADi; used for the ``peak``, ``joint_peaks`` and ``energy`` objectives (epigraph form),
  warm-started from the rms least-squares solution. A lexicographic objective
  (``peak_then_joints``) takes two IPOPT phases per start: its first phase (``peak``) to ``T*``,
  then its own NLP with the epigraph variables bounded by ``T*·(1 + slack)``.

``auto`` chains them: least squares first (on the rms objective when the objective has no
least-squares form), then IPOPT only when the objective needs it or a constraint is still
violated.

Every start is prepared the same way: free lengths are moved into the interval the
start's spring lengths allow (``max L/ρ ≤ l0 ≤ min L``), and the variables the torque is
linear in (stiffness, initial tension) are set to their bounded linear least-squares
optimum for the start's geometry (kept ≥ 10 % into their range so that no spring starts at
``k = 0``, where its anchors would have no gradient). Each start then runs with the
iteration budget, and the starts within 25 % of the best that stopped on the budget are
continued with a larger one ("screen, then polish"), from where they stopped: a start IPOPT
stopped goes on from its last iterate and multipliers (:meth:`_MultiStartSolver._warm`, which also
starts a re-solve of a nearby problem, ``solve_problem(multipliers=...)``). The best feasible start wins; for a
lexicographic objective, the one with the lowest tiebreak among those within ``slack`` of the best value.

Starts are independent: with ``workers`` > 1 the starts (and then the polish runs) go to a pool of
worker processes forked from this one, which inherit the problem and its compiled residual (no
pickling, no recompilation). Each start computes exactly what it computes alone, so the result is
bit for bit the sequential one. Without ``workers``, :func:`default_workers` decides.
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import os
import sys
import time

import casadi as ca
import numpy as np
from threadpoolctl import threadpool_limits

from springbalance.errors import InputError, Interrupted, SolverError
from springbalance.design.structured_nlp import NotStructured, StructuredNlp, warm_start_options
from springbalance.design.torque_model import BlockEvaluator, compiled, count_from_environment, use_one_thread
from springbalance.model.sobol import sobol_engine

METHODS = ("auto", "least_squares", "ipopt")
FEASIBILITY_TOLERANCE = 1e-6  # [m or N]
#: a lexicographic second phase may exceed its bound by this much of the torque scale S (IPOPT relaxes
#: bounds and rows to its tolerance); starts within it (and ``slack``) of the best value count as tied.
EPIGRAPH_TOLERANCE = 1e-6


@dataclasses.dataclass
class StartRecord:
    """What one start of the multi-start did."""

    index: int
    z0: np.ndarray
    x: np.ndarray
    objective: float
    max_violation: float
    status: str
    iterations: int
    seconds: float
    tiebreak: float = float("nan")  # second criterion of a lexicographic objective (NaN otherwise)
    #: IPOPT's multipliers of the NLP rows at ``x`` (CasADi's sign, ≤ 0) when IPOPT ended the start, else None
    multipliers: np.ndarray | None = None

    @property
    def feasible(self) -> bool:
        return self.max_violation <= FEASIBILITY_TOLERANCE and np.isfinite(self.objective)

    def to_dict(self) -> dict:
        return {"index": self.index, "objective": self.objective, "max_violation": self.max_violation,
                "status": self.status, "iterations": self.iterations, "seconds": self.seconds,
                "feasible": bool(self.feasible), "x": self.x.tolist(),
                **({"tiebreak": self.tiebreak} if np.isfinite(self.tiebreak) else {})}


@dataclasses.dataclass
class Solution:
    """What the multi-start found: the best feasible design vector and the record of every start.

    Attributes:
        x: the chosen design vector in physical units (``problem.variables.names`` order).
        starts: one :class:`StartRecord` per start (polished starts replace their screening record).
        method: the solver method asked for (``auto``, ``least_squares`` or ``ipopt``).
        seed: the seed of the start points.
        status: the solver status of the chosen start.
        multipliers: IPOPT's multipliers of the NLP rows at ``x`` when IPOPT ended the chosen start (else
            None): a solve of a nearby problem with the same rows may start from them (``solve_problem``).
    """

    x: np.ndarray
    starts: list
    method: str
    seed: int
    status: str
    multipliers: np.ndarray | None = None


def start_points(problem, starts: int, seed: int, initial=None, fixed=None) -> np.ndarray:
    """Scaled start points: ``initial`` (physical units; one point, or one per row of a 2-D array)
    or the problem's initial guess, then scrambled Sobol points in [0, 1]^n up to ``starts`` points
    in all; the variables of the boolean mask ``fixed`` keep their value of the first point in every
    Sobol point (and each given point its own)."""
    n = problem.variables.size
    guess = problem.variables.start if initial is None else initial
    given = np.clip(problem.unscale(np.atleast_2d(np.asarray(guess, dtype=float))), 0.0, 1.0)
    count = max(int(starts) - given.shape[0], 0)
    if count == 0 or n == 0:
        return given
    sobol = sobol_engine(n, np.random.default_rng(seed))
    others = sobol.random(1 << int(np.ceil(np.log2(count)))) if count > 1 else sobol.random(1)
    points = np.vstack([given, others[:count]])
    if fixed is not None:
        points[given.shape[0]:, fixed] = given[0, fixed]
    return points


# ---------------------------------------------------------------------- worker processes
WORKERS_ENV = "SPRINGBALANCE_WORKERS"
#: by default, starts go to the pool only when one start is expected to take longer than this [s]
#: (a pool's start-up, forking and collecting, costs 10-20 ms for the demo's process, more for a larger one)
POOL_MIN_SECONDS = 0.1
_DEFAULT_WORKERS: contextvars.ContextVar = contextvars.ContextVar("springbalance_workers", default=None)
_WORKER_SOLVER = None  # the solver a forked worker runs its starts with (set before the fork)
_IN_WORKER = False


def default_workers() -> int:
    """Worker processes of a solve that does not say: ``$SPRINGBALANCE_WORKERS`` when set, else
    ``os.cpu_count()``."""
    value = count_from_environment(WORKERS_ENV)
    if value is not None:
        return value
    return os.cpu_count() or 1


def check_workers(workers) -> int | None:
    """``workers`` as an int ≥ 1, or None (the default); InputError otherwise."""
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise InputError(f"workers must be an integer ≥ 1, got {workers!r}")
    return int(workers)


@contextlib.contextmanager
def workers_default(workers):
    """Within the block, solves that do not pass ``workers`` use this number (None: no change).
    :meth:`DesignProblem.solve` sets it, so that the solves it makes along the way (coil start,
    clearance fit, wire rounding) use the caller's choice."""
    workers = check_workers(workers)
    token = _DEFAULT_WORKERS.set(workers if workers is not None else _DEFAULT_WORKERS.get())
    try:
        yield
    finally:
        _DEFAULT_WORKERS.reset(token)


def _pool_workers(problem, workers, tasks: int) -> tuple[int, bool]:
    """``(processes, asked)``: how many processes may run ``tasks`` starts, and whether the caller
    asked for them (else :class:`_StartRunner` first checks that a start is worth a pool). 1 inside a
    worker (ours, or a daemonic process, which may not have children), without ``fork`` or for one
    task; else ``min(workers, tasks)``."""
    import multiprocessing

    if (_IN_WORKER or tasks < 2 or multiprocessing.current_process().daemon or sys.platform == "darwin"
            or "fork" not in multiprocessing.get_all_start_methods()):
        return 1, False
    chosen = check_workers(workers)
    if chosen is None:
        chosen = _DEFAULT_WORKERS.get()
    asked = chosen is not None
    if chosen is None:
        chosen = default_workers()
    return max(1, min(chosen, tasks)), asked


def _mark_worker() -> None:
    global _IN_WORKER
    _IN_WORKER = True
    use_one_thread()


def _run_in_worker(index, z0, prepare, multipliers, max_iterations):
    solver = _WORKER_SOLVER
    solver.max_iterations = max_iterations
    return solver.run(index, z0, prepare, multipliers)


class _StartRunner:
    """Runs starts ``(index, z0, prepare, multipliers)`` with a solver, in order: here, or on a pool of
    ``workers`` processes forked from this one (opened when first needed, closed by :meth:`close`).

    Unless ``asked``, the pool must pay for itself: it opens at once when a start is expected to
    last :data:`POOL_MIN_SECONDS` (IPOPT certain or likely, or one residual evaluation × the iteration budget);
    otherwise the first start runs here, and the pool opens for the others only if it took that long.
    Either way each start computes the same numbers.
    """

    def __init__(self, solver, workers: int, asked: bool = True):
        self.solver, self.workers, self.asked = solver, int(workers), bool(asked)
        self._executor = None

    def run(self, tasks, done=None) -> list:
        """The records of ``tasks`` in their order; ``done(record)`` is called as each one finishes."""
        tasks, records = list(tasks), []
        if self.workers > 1 and len(tasks) > 1 and self._executor is None and not self.asked:
            self.asked = True  # decided once, for the polish runs too
            if not self._worth_a_pool(tasks):
                clock = time.perf_counter()
                records.append(self._here(tasks.pop(0), done))
                if time.perf_counter() - clock < POOL_MIN_SECONDS:
                    self.workers = 1
        if self.workers <= 1 or len(tasks) <= 1:
            return records + [self._here(task, done) for task in tasks]
        from concurrent.futures import as_completed

        executor = self._pool()
        futures = [executor.submit(_run_in_worker, *task, self.solver.max_iterations) for task in tasks]
        for future in as_completed(futures):
            if done is not None:
                done(future.result())
        return records + [future.result() for future in futures]

    def _here(self, task, done):
        record = self.solver.run(*task)
        if done is not None:
            done(record)
        return record

    def _worth_a_pool(self, tasks) -> bool:
        """Whether one start is expected to last :data:`POOL_MIN_SECONDS`: IPOPT runs for sure, or
        most likely (the starts go on from IPOPT's multipliers, :meth:`_MultiStartSolver._warm`: least
        squares alone rarely finishes such a start in its short run), or one evaluation of the compiled
        residual times the iteration budget is that long."""
        solver, problem = self.solver, self.solver.problem
        if solver.method == "ipopt" or not problem.objective.least_squares:
            return True
        if any(solver._matches(task[3]) for task in tasks):
            return True
        if not problem.variables.size:
            return False
        residuals = solver._residuals()
        z = np.full(problem.variables.size, 0.5)
        clock = time.perf_counter()
        residuals.normal_equations(z)
        return (time.perf_counter() - clock) * solver.max_iterations >= POOL_MIN_SECONDS

    def _pool(self):
        global _WORKER_SOLVER
        if self._executor is None:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            self.solver.prepare()  # the compiled residual is built here, once, and inherited by the workers
            _WORKER_SOLVER = self.solver
            self._executor = ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("fork"),
                                                 initializer=_mark_worker)
        return self._executor

    def close(self) -> None:
        global _WORKER_SOLVER
        if self._executor is not None:
            self._executor.shutdown(wait=True, cancel_futures=True)
            self._executor = None
            _WORKER_SOLVER = None


def solve_problem(problem, starts=8, seed=0, method="auto", progress=None, max_iterations=100, tolerance=1e-8,
                  polish_iterations=None, *, initial=None, multipliers=None, fixed=None, workers=None):
    """Run every start and return the best feasible design (see :meth:`DesignProblem.solve`).

    Screen, then polish: every start runs with ``max_iterations``; up to three feasible starts
    within 25 % of the best that stopped on the iteration limit (least squares' or IPOPT's) then
    continue from where they stopped for up to ``polish_iterations`` (default 4 × max_iterations).
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
        if len(shape) not in (1, 2) or shape[-1] != problem.variables.size or (len(shape) == 2 and not 1 <= shape[0] <= starts):
            raise InputError(f"initial must hold {problem.variables.size} design variables, one start or up to "
                             f"starts={starts} rows of them; got an array of shape {shape}")
    if method == "least_squares" and not problem.objective.least_squares:
        raise InputError(f"method 'least_squares' cannot minimise objective {problem.objective.name!r}; "
                         "use 'ipopt' or 'auto'")
    # The linear algebra here is small (n ≈ 30 columns): BLAS threads only contend with each
    # other and with the evaluation, badly so on a loaded machine, so use one.
    with threadpool_limits(limits=1, user_api="blas"):
        solver = _MultiStartSolver(problem, method, max_iterations, tolerance, _fixed_mask(problem, fixed))
        runner = _StartRunner(solver, *_pool_workers(problem, workers, starts))
        try:
            return _solve(problem, runner, starts, seed, method, progress, max_iterations, polish_iterations, initial,
                          multipliers)
        finally:
            runner.close()


def _fixed_mask(problem, names) -> np.ndarray:
    """The boolean mask of the design variables ``names`` (InputError for a name that is not one)."""
    mask = np.zeros(problem.variables.size, dtype=bool)
    known = {name: index for index, name in enumerate(problem.variables.names)}
    for name in names or ():
        if name not in known:
            raise InputError(f"fixed: {name!r} is not a design variable of this problem")
        mask[known[name]] = True
    return mask


def _solve(problem, runner, starts, seed, method, progress, max_iterations, polish_iterations, initial=None,
           multipliers=None):
    points = start_points(problem, starts, seed, initial, runner.solver.fixed)
    if progress is None:
        progress = len(points) > 1 and sys.stderr.isatty()
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(points), desc="starts", unit="start")
    finished = []

    def done(record):
        finished.append(record)
        if bar is not None:
            best = min((r.objective for r in finished if r.feasible), default=float("nan"))
            bar.set_postfix(best=f"{best:.4g}")
            bar.update()

    try:
        given = 1 if initial is None else np.atleast_2d(initial).shape[0]
        records = runner.run([(index, points[index], True, multipliers if index < given else None)
                              for index in range(len(points))], done)
    except KeyboardInterrupt:
        if bar is not None:
            bar.close()
        feasible = [record for record in finished if record.feasible]
        raise Interrupted(f"interrupted: {len(finished)} of {len(points)} starts had finished",
                          problem=problem, starts=sorted(finished, key=lambda record: record.index),
                          total=len(points), best_x=_best(feasible, problem).x if feasible else None) from None
    if bar is not None:
        bar.close()
    polish = 4 * max_iterations if polish_iterations is None else int(polish_iterations)
    polish = polish if problem.variables.size else 0
    feasible = [record for record in records if record.feasible]
    if not feasible and polish > 0:
        # no start is feasible yet: continue those the budget stopped, the closest to feasible first
        stopped = sorted((r for r in records if _stopped_by_budget(r)), key=lambda record: record.max_violation)[:3]
        _polish(runner, problem, records, stopped, polish, lambda new, old: new.max_violation < old.max_violation,
                len(points), None)
        feasible = [record for record in records if record.feasible]
    if not feasible:
        summary = "; ".join(f"start {r.index}: {r.status}, violation {r.max_violation:.3g}" for r in records)
        raise SolverError(f"no start gave a feasible design ({summary})", problem=problem, starts=records)
    best = _best(feasible, problem)
    if polish > 0:
        # continue the starts that are close to the best and were stopped by the budget
        candidates = sorted((r for r in feasible if _stopped_by_budget(r) and r.objective <= 1.25 * best.objective),
                            key=lambda record: record.objective)[:3]
        _polish(runner, problem, records, candidates, polish,
                lambda new, old: new.feasible and new.objective <= old.objective, len(points), best.x)
        best = _best([r for r in records if r.feasible], problem)
    return Solution(best.x, records, method, seed, best.status, best.multipliers)


def _stopped_by_budget(record: StartRecord) -> bool:
    """Whether the start stopped on its iteration limit (least squares' or IPOPT's)."""
    return "iteration limit" in record.status or "Maximum_Iterations_Exceeded" in record.status


def _polish(runner, problem, records, candidates, iterations, better, total, best_x) -> None:
    """Continue ``candidates`` (records of ``records``) from where they stopped for up to ``iterations``;
    a continued start replaces its record when ``better(new, old)``."""
    if not candidates:
        return
    runner.solver.max_iterations = iterations
    try:
        # from where each stopped: its design, and IPOPT's multipliers when IPOPT stopped it
        continued = runner.run([(record.index, problem.unscale(record.x), False, record.multipliers)
                                for record in candidates])
    except KeyboardInterrupt:
        raise Interrupted(f"interrupted while polishing: all {total} starts had finished",
                          problem=problem, starts=records, total=total, best_x=best_x) from None
    for record, polished in zip(candidates, continued):
        polished.z0 = record.z0
        polished.status = f"{polished.status} (polished after {record.iterations} iterations)"
        polished.iterations += record.iterations
        polished.seconds += record.seconds
        if better(polished, record):
            records[records.index(record)] = polished


def _best(records: list, problem) -> StartRecord:
    """The record of lowest objective; for a lexicographic objective, of those within ``slack`` of
    the lowest, the one of lowest tiebreak."""
    objective = problem.objective
    best = min(records, key=lambda record: record.objective)
    if objective.first_phase is None:
        return best
    window = best.objective * (1.0 + objective.slack) + EPIGRAPH_TOLERANCE * problem.torque_scale
    tied = [r for r in records if r.objective <= window]
    return min(tied, key=lambda record: (record.tiebreak if np.isfinite(record.tiebreak) else np.inf, record.objective))


class _MultiStartSolver:
    def __init__(self, problem, method, max_iterations, tolerance, fixed=None):
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
    def run(self, index: int, z0: np.ndarray, prepare: bool = True, nlp_multipliers: np.ndarray | None = None) -> StartRecord:
        """One start from ``z0`` (scaled); ``prepare``: fit the linear variables and free lengths first.
        ``nlp_multipliers``: IPOPT's multipliers of the NLP rows at ``z0`` (those of a nearby problem's
        solution, or those IPOPT stopped this start with): the start then goes on from that primal-dual
        point (:meth:`_warm`)."""
        problem = self.problem
        clock = time.perf_counter()
        z, status, iterations, lam_g, evaluation = np.array(z0, dtype=float), "evaluated", 0, None, None
        if not self.fixed.all():
            z, status, iterations, lam_g, evaluation = (self._warm(z, nlp_multipliers) if self._matches(nlp_multipliers)
                                                        else self._cold(z, prepare))
        if evaluation is None:
            evaluation = problem.evaluate(problem.scale(z))
        tiebreak = problem.objective.tiebreak(evaluation.tau * problem.weights, evaluation.potential, problem.path_steps)
        violation = self._violation(evaluation)
        return StartRecord(index, np.asarray(z0), evaluation.x, problem.objective_value(evaluation),
                           violation, status, iterations, time.perf_counter() - clock, tiebreak, lam_g)

    def _cold(self, z, prepare):
        """Least squares first (``auto``, ``least_squares``), then IPOPT when asked for, for an objective
        without least-squares structure, or for a constraint that least squares left violated.
        Returns ``(z, status, iterations, lam_g, evaluation)`` (``lam_g``: IPOPT's row multipliers, None
        without IPOPT; ``evaluation``: the design ``z`` evaluated, when it was on the way, else None)."""
        problem = self.problem
        status, iterations, multipliers = "evaluated", 0, None
        if self.method in ("auto", "least_squares"):
            z, status, iterations, multipliers = self._least_squares(z, prepare)
        needs_nlp, evaluation = self.method == "ipopt" or (self.method == "auto" and not problem.objective.least_squares), None
        if not needs_nlp and self.method == "auto" and (problem.model.n_constraints or problem.linear_matrix()[1].size):
            evaluation = problem.evaluate(problem.scale(z))   # (only then is the design evaluated here)
            needs_nlp = self._violation(evaluation) > FEASIBILITY_TOLERANCE
        if not needs_nlp:
            return z, status, iterations, None, evaluation
        evaluation = evaluation if evaluation is not None else problem.evaluate(problem.scale(z))
        z, status, more, lam_g = self._ipopt_solve(z, evaluation,
                                                   multipliers=multipliers if problem.objective.least_squares else None)
        return z, status, iterations + more, lam_g, None

    def _warm(self, z, lam_g):
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
        z, status, more, lam_g = self._ipopt_solve(z, evaluation, multipliers=multipliers)
        return z, status, iterations + more, lam_g, None

    def _violation(self, evaluation) -> float:
        """The largest violation of a constraint row or a linear row [m or N] of an evaluated design."""
        return max(evaluation.max_violation, self.problem.linear_violation(evaluation.x))

    def _matches(self, lam_g) -> bool:
        """Whether a start may begin from IPOPT's multipliers ``lam_g``: a method that runs IPOPT, a
        one-phase objective, constraint rows when least squares comes first, and an NLP of as many rows."""
        problem = self.problem
        if lam_g is None or self.method == "least_squares" or problem.objective.first_phase is not None:
            return False
        if problem.objective.least_squares and self.method == "auto" and not self._residuals().n_constraint_rows:
            return False
        self._ipopt_solvers()
        return np.size(lam_g) == self._ipopt.nlp.n_rows

    # ------------------------------------------------------------------ least squares
    def _least_squares(self, z0, prepare=True, multipliers=None, budget=None):
        """Bounded Gauss–Newton (SciPy TRF) on the residuals; practical constraints by an
        augmented Lagrangian whose penalty rows ``max(0, λ - μ c)/√μ`` join the residuals.

        Returns ``(z, status, iterations, multipliers)``: ``multipliers`` are the estimates
        ``ν = 2 max(0, λ - μ c(z))`` of the constraint rows' KKT multipliers for the cost ``rᵀr``
        (scaled rows, as :meth:`_LeastSquaresResiduals.constraint_rows`; None without rows)."""
        ls = self._residuals()
        ls.set_penalty(None, 0.0)
        z = np.clip(z0, 0.0, 1.0)
        if prepare:
            z = self._fit_linear_variables(z)
        multipliers = np.zeros(ls.n_constraint_rows) if multipliers is None else np.asarray(multipliers, dtype=float)
        penalty, iterations, status = 10.0, 0, "least_squares: not run"
        previous_violation = np.inf
        for _ in range(12 if ls.n_constraint_rows else 1):
            if ls.n_constraint_rows:
                ls.set_penalty(multipliers, penalty)
            z, used, status = self._trust_region(ls, z, budget)
            iterations += used
            if not ls.n_constraint_rows:
                break
            rows = ls.constraint_rows(z)
            violation = float(max(0.0, -np.min(rows)))
            if violation * ls.smallest_row_scale <= FEASIBILITY_TOLERANCE:
                break
            multipliers = np.maximum(0.0, multipliers - penalty * rows)
            if violation > 0.25 * previous_violation:
                penalty *= 10.0
            previous_violation = violation
        if not ls.n_constraint_rows:
            return z, status, iterations, None
        # ∇(rᵀr + Σ max(0, λ - μc)²/μ) = ∇(rᵀr) - Σ 2 max(0, λ - μc) ∇c
        return z, status, iterations, 2.0 * np.maximum(0.0, multipliers - penalty * ls.constraint_rows(z))

    def _residuals(self) -> "_LeastSquaresResiduals":
        problem = self.problem
        if self._ls is None:   # compiled once per problem, kept across solves (the fit loop re-solves)
            if problem.least_squares_cache is None:
                problem.least_squares_cache = _LeastSquaresResiduals(problem)
            self._ls = problem.least_squares_cache
        return self._ls

    def _trust_region(self, ls, z, budget=None):
        """SciPy's bounded trust-region-reflective least squares on the *compressed* residual.

        With ``JᵀJ = V Λ Vᵀ`` and ``R = Λ^½ Vᵀ``, ``q = Λ^-½ Vᵀ Jᵀ r`` (directions with
        ``λ ≤ 1e-13 λ_max`` dropped) and ``ρ² = |r|² - |q|²``, the residual ``(q, ρ)`` with
        Jacobian ``[R; 0]`` has the same norm and the same Gauss–Newton model,
        ``|r + J δ|² = |q + R δ|² + ρ²``, as the full one. The solver's iterates are unchanged
        while its linear algebra shrinks from N·nv rows to n+1 (the Gram matrix ``JᵀJ`` and ``Jᵀr``
        are summed over blocks of samples, :meth:`_LeastSquaresResiduals.normal_equations`).
        """
        from scipy.optimize import least_squares  # imported when first used: SciPy's optimize costs 0.2 s at start-up

        cache = {}
        held = self.fixed.any()
        free = ~self.fixed
        full = z.copy()

        def compressed(zz):
            key = zz.tobytes()
            if key not in cache:
                if held:   # the held variables' columns left out
                    full[free] = zz
                    gram, projected, squares = ls.normal_equations(full)   # summed over blocks of samples
                    gram, projected = gram[np.ix_(free, free)], projected[free]
                else:
                    gram, projected, squares = ls.normal_equations(zz)   # summed over blocks of samples
                eigenvalues, vectors = np.linalg.eigh(gram)
                keep = eigenvalues > 1e-13 * max(float(eigenvalues[-1]), 1e-300)
                root = np.sqrt(eigenvalues[keep])
                n = gram.shape[1]
                reduced, jacobian = np.zeros(n + 1), np.zeros((n + 1, n))
                reduced[: root.size] = (vectors[:, keep].T @ projected) / root
                jacobian[: root.size] = root[:, None] * vectors[:, keep].T
                reduced[n] = np.sqrt(max(squares - float(reduced[:n] @ reduced[:n]), 0.0))
                cache.clear()
                cache[key] = (reduced, jacobian)
            return cache[key]

        result = least_squares(lambda zz: compressed(zz)[0], z[free], jac=lambda zz: compressed(zz)[1],
                               bounds=(0.0, 1.0), method="trf", x_scale="jac", ftol=self.tolerance, xtol=1e-10,
                               gtol=1e-10, max_nfev=self.max_iterations if budget is None else budget)
        full[free] = np.clip(result.x, 0.0, 1.0)
        return full, int(result.nfev), f"least_squares: {_STATUS.get(result.status, result.message)}"

    def _fit_linear_variables(self, z):
        """Replace the start's stiffnesses and initial tensions by their bounded linear least-squares
        optimum for the start's geometry. The residual is exactly affine in them,
        ``r(z) = r(z0) + J_lin (z_lin - z0_lin)``, so one evaluation and one BVLS solve suffice.
        This keeps a start from wasting its budget on a stiffness guess off by orders of magnitude
        (and from stalling at k = 0, where the anchors have no gradient)."""
        from scipy.optimize import lsq_linear

        z = self._feasible_free_lengths(z)
        linear = [index for index in self.problem.model.linear_indices if not self.fixed[index]]
        if not linear:
            return z
        r, columns = self._ls.linear_columns(z, linear)
        # Keep every stiffness at least 10 % into its range: at k = 0 a spring's anchors have no
        # gradient (a saddle the start could not leave); the solver may still drive k to 0.
        # Other linear variables (initial tension, constant force, preload) may start anywhere.
        names = self.problem.variables.names
        floor = np.array([0.1 if names[i].endswith(".stiffness") else 0.0 for i in linear])
        fit = lsq_linear(columns, columns @ z[linear] - r, bounds=(floor, np.ones(len(linear))), method="bvls")
        if not fit.success:
            return z
        z = z.copy()
        z[linear] = np.clip(fit.x, floor, 1.0)
        return z

    def _feasible_free_lengths(self, z):
        """Move each free length of the start into the interval its spring's length range allows
        (``Spring.free_length_interval``: e.g. ``max L/ρ ≤ l0 ≤ min L`` for an extension spring),
        where that interval meets the bounds, so that the augmented Lagrangian starts feasible
        for these constraints."""
        problem = self.problem
        evaluation = problem.evaluate(problem.scale(z))
        names = {name: i for i, name in enumerate(problem.variables.names)}
        lower, upper = problem.variables.bounds()
        z = z.copy()
        for column, spring in enumerate(problem.springs):
            index = names.get(f"{spring.name}.free_length")
            if index is None or self.fixed[index]:
                continue
            lengths = evaluation.lengths[:, column]
            spring_low, spring_high = spring.free_length_interval(lengths)
            low, high = max(lower[index], spring_low), min(upper[index], spring_high)
            if low <= high:
                value = float(np.clip(problem.scale(z)[index], low, high))
                z[index] = (value - lower[index]) / (upper[index] - lower[index])
        return np.clip(z, 0.0, 1.0)

    # ------------------------------------------------------------------ IPOPT
    def _nlpsol(self, objective=None):
        """IPOPT on the problem's NLP (of ``objective``, default its own): with derivatives from the
        per-sample structure on a working set of rows (:mod:`~springbalance.design.structured_nlp`), or
        CasADi's own of the plain NLP when it lacks that structure."""
        options = {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes",
                   "ipopt.tol": min(self.tolerance, 1e-8), "ipopt.acceptable_tol": 1e-8,
                   "ipopt.mu_strategy": "adaptive"}
        problem = self.problem
        key = None if objective is None else objective.name
        cached = problem.nlp_cache.get(key)
        if cached is None or cached[0] is not problem.linear_rows:   # new linear rows: a new NLP replaces it
            try:
                nlp = StructuredNlp(problem, objective)
            except NotStructured:
                nlp = problem.build(objective)
            cached = problem.nlp_cache[key] = (problem.linear_rows, nlp)
        nlp = cached[1]
        return _StructuredIpopt(nlp, options) if isinstance(nlp, StructuredNlp) else _PlainIpopt(nlp, options)

    def _ipopt_solvers(self) -> None:
        """Build the NLP solvers once: the objective's, and a lexicographic objective's first phase."""
        if self._ipopt is None:
            first_phase = self.problem.objective.first_phase
            if first_phase is not None:
                self._first = self._nlpsol(first_phase)
            self._ipopt = self._nlpsol()

    def _ipopt_solve(self, z, evaluation, multipliers=None, lam_g=None):
        """IPOPT from ``z``; returns ``(z, status, iterations, lam_g)``, ``lam_g``: IPOPT's multipliers of the
        NLP rows at ``z`` (None for a lexicographic objective, whose last NLP has its phase's bounds).

        IPOPT starts warm from ``multipliers``, the least-squares estimates of the constraint rows'
        multipliers when the objective is the least-squares cost itself, or from ``lam_g``, multipliers
        of the NLP rows (CasADi's sign)."""
        problem = self.problem
        self._ipopt_solvers()
        first_phase = problem.objective.first_phase
        if first_phase is None:
            return self._ipopt_run(self._ipopt, z, evaluation, multipliers=multipliers, lam_g=lam_g)
        # lexicographic: the first phase's optimum T*, then the objective's own NLP with its
        # epigraph variables bounded by T*·(1 + slack)
        z1, status1, iterations1, _ = self._ipopt_run(self._first, z, evaluation)
        first = problem.evaluate(problem.scale(z1))
        weighted = first.tau * problem.weights
        bound = problem.objective.phase_two_bound(first_phase.value(weighted, first.potential, problem.path_steps),
                                                  problem.torque_scale)
        upper = self._ipopt.nlp.upper.copy()
        upper[self._ipopt.nlp.n_design:] = bound
        z2, status2, iterations2, _ = self._ipopt_run(self._ipopt, z1, first, upper=upper)
        second = problem.evaluate(problem.scale(z2))
        value = problem.objective.value(second.tau * problem.weights, second.potential, problem.path_steps)
        kept = (second.max_violation <= max(FEASIBILITY_TOLERANCE, first.max_violation)
                and value <= (bound + EPIGRAPH_TOLERANCE) * problem.torque_scale)
        status = f"{status1}, then {status2.removeprefix('ipopt: ')}{'' if kept else ' (not kept)'}"
        return (z2 if kept else z1), status, iterations1 + iterations2, None

    def _ipopt_run(self, ipopt, z, evaluation, upper=None, multipliers=None, lam_g=None):
        problem, nlp = self.problem, ipopt.nlp
        start = z
        if multipliers is not None:   # CasADi's sign: a row held at its lower bound has λ ≤ 0
            lam_g = -problem.nlp_row_multipliers(multipliers, nlp.n_rows)
        if nlp.size > nlp.n_design:
            extra = nlp.extra_start(evaluation.tau * problem.weights)
            if upper is not None:
                extra = np.minimum(extra, upper[nlp.n_design:])
            start = np.concatenate([z, extra])
        lower, upper = nlp.lower.copy(), (nlp.upper if upper is None else upper).copy()
        lower[: nlp.n_design][self.fixed] = upper[: nlp.n_design][self.fixed] = z[self.fixed]
        x, status, iterations, lam_g = ipopt.solve(start, lower, upper, self.max_iterations, lam_g)
        return np.clip(x[: nlp.n_design], 0.0, 1.0), f"ipopt: {status}", iterations, lam_g


class _StructuredIpopt:
    """IPOPT through :class:`~springbalance.design.structured_nlp.StructuredNlp` (working set of rows)."""

    def __init__(self, structured, options):
        self.structured, self.nlp, self.options = structured, structured.nlp, options

    def solve(self, start, lower, upper, max_iterations, lam_g=None):
        return self.structured.solve(start, lower, upper, self.options, max_iterations, lam_g)


class _PlainIpopt:
    """IPOPT on the plain NLP, every row, CasADi's derivatives (for an NLP without the per-sample structure)."""

    def __init__(self, nlp, options):
        self.nlp, self.options, self._solvers = nlp, options, {}

    def solve(self, start, lower, upper, max_iterations, lam_g=None):
        warm = lam_g is not None
        solver = self._solvers.get((max_iterations, warm))
        if solver is None:
            nlp = self.nlp
            solver = self._solvers[max_iterations, warm] = ca.nlpsol(
                "springbalance", "ipopt", {"x": nlp.z, "f": nlp.cost, "g": nlp.rows},
                {**self.options, "ipopt.max_iter": int(max_iterations), **(warm_start_options() if warm else {})})
        arguments = {"lam_g0": lam_g} if warm else {}
        solution = solver(x0=start, lbx=lower, ubx=upper, lbg=0.0, ubg=np.inf, **arguments)
        stats = solver.stats()
        return (np.array(solution["x"]).reshape(-1), str(stats.get("return_status", "unknown")),
                int(stats.get("iter_count", 0)), np.array(solution["lam_g"]).reshape(-1))


class _LeastSquaresResiduals:
    """Scaled residuals ``r(z)`` and exact Jacobian ``dr/dz`` of a least-squares objective.

    One per-sample CasADi function of the *scaled* variables ``z`` gives the sample's
    residual rows and their transposed Jacobian, already scaled, so that the mapped,
    compiled evaluation lands in NumPy buffers that *are* blocks of ``r`` and ``J`` (no copies):

    - ``rms`` (and the warm-start phase of ``peak``/``energy``): ``w ⊙ tau / (S·sqrt(N·nv))``;
    - ``pe_variance``: the total potential over ``P·sqrt(N)``, centred here in NumPy;
    - constraint rows ``c / scale`` (≥ 0 when feasible) for the augmented Lagrangian, whose
      penalty rows ``max(0, λ - μ c)/√μ`` follow the objective rows when a penalty is set.

    The solver needs only ``JᵀJ``, ``Jᵀr`` and ``rᵀr`` (:meth:`normal_equations`): they are summed
    over blocks of samples (:class:`~springbalance.design.torque_model.BlockEvaluator`), so that the
    Jacobian never exists for all samples at once. ``pe_variance``, whose rows are centred over
    all samples, and :func:`refine` assemble the full ``r`` and ``J`` (:meth:`residuals_and_jacobian`).

    **Rows no variable moves.** Sample data that is zero at every sample (a spring body's Jacobian
    columns of the joints beyond it) enters the per-sample function as a structural zero. Residual rows whose Jacobian is then structurally zero (the wrist joints of an
    arm whose springs end on the forearm, a joint of weight 0) are constant in ``z``: the function
    gives their values after the others' (for ``rᵀr``) but no Jacobian rows, and ``JᵀJ``, ``Jᵀr``
    are summed over the :attr:`n_moving` other rows only. The numbers are the same: only the terms
    that are exactly zero are left out.
    """

    def __init__(self, problem, block: int | None = None):
        self.problem = problem
        self.variance = problem.objective.name == "pe_variance"
        model = problem.model
        lower, upper = problem.variables.bounds()
        n, nv = problem.workspace.size, problem.mechanism.nv
        blocks = model.constraint_blocks
        self.row_scale = np.array([block.scale for block in blocks]) if blocks else np.ones(0)
        self.n_sample_rows = n * len(blocks)
        self.bounds = (lower, upper)

        z, data, (tau, potential, _, _, rows) = problem.scaled_sample()
        if self.variance:
            residual = potential / (problem.potential_scale * np.sqrt(n))
        else:
            residual = tau * ca.DM(problem.weights / (problem.torque_scale * np.sqrt(n * nv)))
        # the rows z moves first, then the constant ones; order[i]: the residual row at output row i
        moving = sorted(set(ca.jacobian(residual, z).sparsity().get_triplet()[0]))
        self.order = np.array(moving + [row for row in range(residual.numel()) if row not in moving], dtype=int)
        self.n_moving = len(moving)
        residual = residual[self.order.tolist()]
        scaled_rows = rows / ca.DM(self.row_scale) if blocks else rows
        function = ca.Function("scaled_residual", [z, data],
                               [residual, ca.densify(ca.jacobian(residual[: self.n_moving], z).T), scaled_rows,
                                ca.jacobian(scaled_rows, z).T])
        self.function = compiled(function)
        self.evaluator = BlockEvaluator(self.function, problem.data, block)
        self.multipliers, self.penalty = None, 0.0
        self._rows_z, self._rows = None, None            # the sample constraint rows at _rows_z
        self._normal_key, self._normal = None, None      # (z, penalty, multipliers) → (JᵀJ, Jᵀr, rᵀr)
        self._full_z, self._full = None, None            # z → full outputs (residuals_and_jacobian)

    def set_penalty(self, multipliers, penalty: float) -> None:
        self.multipliers, self.penalty = multipliers, penalty

    def _linear(self):
        """The problem's linear rows over ``z``, scaled: ``(A, b)`` with rows ``A z + b`` (empty when none)."""
        matrix, offset = self.problem.linear_matrix()
        if not offset.size:
            return matrix, offset
        lower, upper = self.bounds
        scale = self.problem.linear_rows.scale
        return matrix * (upper - lower)[None, :] / scale, (matrix @ lower + offset) / scale

    @property
    def n_constraint_rows(self) -> int:
        return self.n_sample_rows + self._linear()[1].size

    @property
    def smallest_row_scale(self) -> float:
        """The smallest row scale [m or N]: a scaled violation times it is a physical one (at most)."""
        scales = list(self.row_scale) + ([self.problem.linear_rows.scale] if self._linear()[1].size else [])
        return float(min(scales)) if scales else 1.0

    # ---------------------------------------------------------------- block pass
    def _blocks(self, z):
        """The evaluator's blocks at ``z``; records the sample constraint rows on the way."""
        z = np.array(z, dtype=float)
        rows_all = np.empty(self.n_sample_rows)
        n_c = self.row_scale.size
        for start, stop, outputs in self.evaluator.blocks(z):
            if n_c:
                rows_all[start * n_c: stop * n_c] = outputs[2].reshape(-1)
            yield start, stop, outputs
        self._rows_z, self._rows = z, rows_all

    def constraint_rows(self, z) -> np.ndarray:
        """Scaled constraint rows (N·n_c, then the linear rows), ≥ 0 when feasible."""
        if self._rows_z is None or not np.array_equal(z, self._rows_z):
            for _ in self._blocks(z):
                pass
        matrix, offset = self._linear()
        return np.concatenate([self._rows, matrix @ z + offset])

    def normal_equations(self, z) -> tuple[np.ndarray, np.ndarray, float]:
        """``(JᵀJ, Jᵀr, rᵀr)`` of the residual (with the penalty rows when a penalty is set) at ``z``,
        summed block by block."""
        key = (np.array(z, dtype=float).tobytes(), self.penalty,
               None if self.multipliers is None else np.asarray(self.multipliers).tobytes())
        if self._normal_key == key:
            return self._normal
        if self.variance:
            r, J = self.residuals_and_jacobian(z)
            normal = (J.T @ J, J.T @ r, float(r @ r))
        else:
            normal = self._accumulate(np.array(z, dtype=float))
        self._normal_key, self._normal = key, normal
        return normal

    def _accumulate(self, z):
        n_x = self.problem.variables.size
        n_c = self.row_scale.size
        gram, projected, squares = np.zeros((n_x, n_x)), np.zeros(n_x), 0.0
        penalised = self.multipliers is not None
        if penalised:
            root = np.sqrt(self.penalty)
            multipliers = np.asarray(self.multipliers)
        for start, stop, (residual, jacobian, rows, row_jacobian) in self._blocks(z):
            r, J = residual.reshape(-1), jacobian.reshape(-1, n_x)
            moving = r if self.n_moving == self.order.size else residual.reshape(-1, self.order.size)[:, : self.n_moving].reshape(-1)
            gram += J.T @ J
            projected += J.T @ moving
            squares += float(r @ r)
            if penalised and n_c:
                shifted = multipliers[start * n_c: stop * n_c] - self.penalty * rows.reshape(-1)
                active = shifted > 0
                if np.any(active):
                    penalty_r = shifted[active] / root
                    penalty_J = -root * row_jacobian.reshape(-1, n_x)[active]
                    gram += penalty_J.T @ penalty_J
                    projected += penalty_J.T @ penalty_r
                    squares += float(penalty_r @ penalty_r)
        matrix, offset = self._linear()
        if penalised and offset.size:
            shifted = multipliers[self.n_sample_rows:] - self.penalty * (matrix @ z + offset)
            active = shifted > 0
            penalty_r = shifted[active] / root
            penalty_J = -root * matrix[active]
            gram += penalty_J.T @ penalty_J
            projected += penalty_J.T @ penalty_r
            squares += float(penalty_r @ penalty_r)
        return gram, projected, squares

    def linear_columns(self, z, columns) -> tuple[np.ndarray, np.ndarray]:
        """The objective residual ``r`` (no penalty rows) and the columns ``columns`` of its Jacobian at ``z``."""
        if self.variance:
            r, J = self._objective_rows(z)
            return r, J[:, columns]
        per_sample = r = J = None
        for start, stop, (residual, jacobian, _, _) in self._blocks(z):
            if r is None:
                per_sample = self.order.size
                r = np.empty(self.evaluator.n_samples * per_sample)
                J = np.empty((r.size, len(columns)))
            r_block, J_block = self._in_row_order(residual, jacobian)
            r[start * per_sample: stop * per_sample] = r_block
            J[start * per_sample: stop * per_sample] = J_block[:, columns]
        return r, J

    def _in_row_order(self, residual, jacobian) -> tuple[np.ndarray, np.ndarray]:
        """``r`` and ``J`` of some samples' outputs in the residual's own row order (sample by sample),
        the constant rows with their zero Jacobian rows put back."""
        n_x, size = self.problem.variables.size, self.order.size
        if self.n_moving == size:
            return residual.reshape(-1), jacobian.reshape(-1, n_x)
        count = residual.shape[0]
        r, J = np.empty((count, size)), np.zeros((count, size, n_x))
        r[:, self.order] = residual.reshape(count, size)
        J[:, self.order[: self.n_moving]] = jacobian.reshape(count, self.n_moving, n_x)
        return r.reshape(-1), J.reshape(-1, n_x)

    # ---------------------------------------------------------------- full arrays
    def _full_outputs(self, z):
        """Every output for all samples at ``z`` (``(N, cols, rows)`` arrays, as SampleEvaluator's)."""
        if self._full_z is None or not np.array_equal(z, self._full_z):
            self._full = self.evaluator.evaluate(np.array(z, dtype=float))
            self._full_z = np.array(z)
        return self._full

    def _objective_rows(self, z):
        residual, jacobian, _, _ = self._full_outputs(z)
        n_x = self.problem.variables.size
        r, J = self._in_row_order(residual, jacobian)
        if self.variance:  # centre the potential (per scenario block): r_i - mean(r), J_i - mean(J)
            blocks = self.problem.model.n_scenarios
            r = (r.reshape(blocks, -1) - r.reshape(blocks, -1).mean(axis=1, keepdims=True)).reshape(-1)
            J = (J.reshape(blocks, -1, n_x) - J.reshape(blocks, -1, n_x).mean(axis=1, keepdims=True)).reshape(-1, n_x)
        return r, J

    def residuals_and_jacobian(self, z):
        """The full residual ``r`` and Jacobian ``J`` (with the penalty rows when a penalty is set)."""
        r, J = self._objective_rows(z)
        if self.multipliers is None:
            return r, J
        _, _, rows, row_jacobian = self._full_outputs(z)
        n_x = J.shape[1]
        matrix, offset = self._linear()
        rows = np.concatenate([rows.reshape(-1), matrix @ z + offset])
        row_jacobian = np.vstack([row_jacobian.reshape(-1, n_x), matrix])
        shifted = self.multipliers - self.penalty * rows
        active = shifted > 0
        penalty_r = np.where(active, shifted, 0.0) / np.sqrt(self.penalty)
        penalty_J = np.zeros((active.size, n_x))
        penalty_J[active] = -np.sqrt(self.penalty) * row_jacobian[active]
        return np.concatenate([r, penalty_r]), np.vstack([J, penalty_J])


_STATUS = {
    -1: "improper input",
    0: "iteration limit reached",
    1: "converged (gradient)",
    2: "converged (cost change)",
    3: "converged (step size)",
    4: "converged (cost change and step size)",
}


def refine(problem, x, iterations: int = 8) -> np.ndarray:
    """A few bounded Gauss–Newton steps on a least-squares problem from design ``x``: each step solves
    the linearised residual exactly within the bounds (BVLS), and is kept only when it lowers the cost.

    Trust-region iterates slow down next to a bound; a design whose optimum lies just inside (or on)
    a bound is finished here to round-off (used by :func:`springbalance.results.payload.payload_range`).
    """
    if not problem.objective.least_squares or problem.model.n_constraints or not problem.variables.size:
        return np.asarray(x, dtype=float)
    from scipy.optimize import lsq_linear

    residuals = _LeastSquaresResiduals(problem)
    z = np.clip(problem.unscale(x), 0.0, 1.0)
    with threadpool_limits(limits=1, user_api="blas"):
        r, J = (np.array(a) for a in residuals.residuals_and_jacobian(z))
        cost = float(r @ r)
        for _ in range(int(iterations)):
            step = lsq_linear(J, -r, bounds=(-z, 1.0 - z), method="bvls")
            trial = np.clip(z + step.x, 0.0, 1.0)
            r_new, J_new = (np.array(a) for a in residuals.residuals_and_jacobian(trial))
            cost_new = float(r_new @ r_new)
            if not cost_new < cost:
                break
            z, r, J, cost = trial, r_new, J_new, cost_new
    return problem.scale(z)
