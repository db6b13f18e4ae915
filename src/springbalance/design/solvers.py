r"""Solvers for a :class:`~springbalance.design.problem.DesignProblem`, with multi-start.

Backends:

- ``least_squares``: for objectives with least-squares structure (``rms``,
  ``pe_variance``) one per-sample CasADi function of the scaled variables gives the residual
  rows and their exact Jacobian; mapped over the samples, JIT-compiled to C when a compiler
  is available, and evaluated straight into NumPy buffers. SciPy's bounded
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
continued with a larger one ("screen, then polish"). The best feasible start wins; for a
lexicographic objective, the one with the lowest tiebreak among those within ``slack`` of the best value.
"""

from __future__ import annotations

import dataclasses
import sys
import time

import casadi as ca
import numpy as np
from scipy.optimize import least_squares, lsq_linear
from scipy.stats import qmc
from threadpoolctl import threadpool_limits

from springbalance.errors import InputError, SolverError
from springbalance.design.torque_model import SampleEvaluator, compiled

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
    """

    x: np.ndarray
    starts: list
    method: str
    seed: int
    status: str


def start_points(problem, starts: int, seed: int, initial=None) -> np.ndarray:
    """Scaled start points: ``initial`` (physical units) or the problem's initial guess, then
    scrambled Sobol points in [0, 1]^n."""
    n = problem.variables.size
    guess = problem.variables.start if initial is None else initial
    first = np.clip(problem.unscale(np.asarray(guess, dtype=float)), 0.0, 1.0)
    if starts <= 1 or n == 0:
        return first[None, :]
    sobol = qmc.Sobol(d=n, scramble=True, seed=np.random.default_rng(seed))
    others = sobol.random(1 << int(np.ceil(np.log2(starts - 1)))) if starts > 2 else sobol.random(1)
    return np.vstack([first, others[: starts - 1]])


def solve_problem(problem, starts=8, seed=0, method="auto", progress=None, max_iterations=100, tolerance=1e-8,
                  polish_iterations=None, *, initial=None):
    """Run every start and return the best feasible design (see :meth:`DesignProblem.solve`).

    Screen, then polish: every start runs with ``max_iterations``; up to three feasible starts
    within 25 % of the best that stopped on the iteration limit then continue from where they
    stopped for up to ``polish_iterations`` (default 4 × max_iterations). Starts that stall far
    from the best cost only their budget, and the chosen design still converges.
    """
    if method not in METHODS:
        raise InputError(f"unknown solver method {method!r}; valid: {', '.join(METHODS)}")
    starts = int(starts)
    if starts < 1:
        raise InputError(f"starts must be ≥ 1, got {starts}")
    if method == "least_squares" and not problem.objective.least_squares:
        raise InputError(f"method 'least_squares' cannot minimise objective {problem.objective.name!r}; "
                         "use 'ipopt' or 'auto'")
    # The linear algebra here is small (n ≈ 30 columns): BLAS threads only contend with each
    # other and with the evaluation, badly so on a loaded machine, so use one.
    with threadpool_limits(limits=1, user_api="blas"):
        return _solve(problem, starts, seed, method, progress, max_iterations, tolerance, polish_iterations, initial)


def _solve(problem, starts, seed, method, progress, max_iterations, tolerance, polish_iterations, initial=None):
    solver = _MultiStartSolver(problem, method, max_iterations, tolerance)
    points = start_points(problem, starts, seed, initial)
    if progress is None:
        progress = len(points) > 1 and sys.stderr.isatty()
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(points), desc="starts", unit="start")
    records = []
    for index in range(len(points)):
        records.append(solver.run(index, points[index]))
        if bar is not None:
            best = min((r.objective for r in records if r.feasible), default=float("nan"))
            bar.set_postfix(best=f"{best:.4g}")
            bar.update()
    if bar is not None:
        bar.close()
    feasible = [record for record in records if record.feasible]
    if not feasible:
        summary = "; ".join(f"start {r.index}: {r.status}, violation {r.max_violation:.3g}" for r in records)
        raise SolverError(f"no start gave a feasible design ({summary})", problem=problem, starts=records)
    best = _best(feasible, problem)
    polish = 4 * max_iterations if polish_iterations is None else int(polish_iterations)
    if polish > 0 and problem.variables.size:
        # continue the starts that are close to the best and were stopped by the budget
        candidates = sorted((r for r in feasible if "iteration limit" in r.status and r.objective <= 1.25 * best.objective),
                            key=lambda record: record.objective)[:3]
        solver.max_iterations = polish
        for record in candidates:
            polished = solver.run(record.index, problem.unscale(record.x), prepare=False)
            polished.z0 = record.z0
            polished.status = f"{polished.status} (polished after {record.iterations} iterations)"
            polished.iterations += record.iterations
            polished.seconds += record.seconds
            if polished.feasible and polished.objective <= record.objective:
                records[records.index(record)] = polished
        best = _best([r for r in records if r.feasible], problem)
    return Solution(best.x, records, method, seed, best.status)


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
    def __init__(self, problem, method, max_iterations, tolerance):
        self.problem = problem
        self.method = method
        self.max_iterations = max_iterations
        self.tolerance = tolerance
        self._ls = None
        self._ipopt = None
        self._nlp = None
        self._first = None  # (nlp, solver) of a lexicographic objective's first phase

    # ------------------------------------------------------------------ one start
    def run(self, index: int, z0: np.ndarray, prepare: bool = True) -> StartRecord:
        problem = self.problem
        clock = time.perf_counter()
        z, status, iterations = np.array(z0, dtype=float), "evaluated", 0
        if problem.variables.size:
            if self.method in ("auto", "least_squares"):
                z, status, iterations = self._least_squares(z, prepare)
            evaluation = problem.evaluate(problem.scale(z))
            needs_nlp = self.method == "ipopt" or (
                self.method == "auto"
                and (not problem.objective.least_squares
                     or max(evaluation.max_violation, problem.linear_violation(evaluation.x)) > FEASIBILITY_TOLERANCE))
            if needs_nlp:
                z, status, more = self._ipopt_solve(z, evaluation)
                iterations += more
        evaluation = problem.evaluate(problem.scale(z))
        tiebreak = problem.objective.tiebreak(evaluation.tau * problem.weights, evaluation.potential, problem.path_steps)
        violation = max(evaluation.max_violation, problem.linear_violation(evaluation.x))
        return StartRecord(index, np.asarray(z0), evaluation.x, problem.objective_value(evaluation),
                           violation, status, iterations, time.perf_counter() - clock, tiebreak)

    # ------------------------------------------------------------------ least squares
    def _least_squares(self, z0, prepare=True):
        """Bounded Gauss–Newton (SciPy TRF) on the residuals; practical constraints by an
        augmented Lagrangian whose penalty rows ``max(0, λ - μ c)/√μ`` join the residuals."""
        problem = self.problem
        if self._ls is None:   # compiled once per problem, kept across solves (the fit loop re-solves)
            if problem.least_squares_cache is None:
                problem.least_squares_cache = _LeastSquaresResiduals(problem)
            self._ls = problem.least_squares_cache
        ls = self._ls
        ls.set_penalty(None, 0.0)
        z = np.clip(z0, 0.0, 1.0)
        if prepare:
            z = self._fit_linear_variables(z)
        multipliers = np.zeros(ls.n_constraint_rows)
        penalty, iterations, status = 10.0, 0, "least_squares: not run"
        previous_violation = np.inf
        for _ in range(12 if ls.n_constraint_rows else 1):
            if ls.n_constraint_rows:
                ls.set_penalty(multipliers, penalty)
            z, used, status = self._trust_region(ls, z)
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
        return z, status, iterations

    def _trust_region(self, ls, z):
        """SciPy's bounded trust-region-reflective least squares on the *compressed* residual.

        With ``JᵀJ = V Λ Vᵀ`` and ``R = Λ^½ Vᵀ``, ``q = Λ^-½ Vᵀ Jᵀ r`` (directions with
        ``λ ≤ 1e-13 λ_max`` dropped) and ``ρ² = |r|² - |q|²``, the residual ``(q, ρ)`` with
        Jacobian ``[R; 0]`` has the same norm and the same Gauss–Newton model,
        ``|r + J δ|² = |q + R δ|² + ρ²``, as the full one. The solver's iterates are unchanged
        while its linear algebra shrinks from N·nv rows to n+1 (the Gram matrix costs one
        BLAS product).
        """
        cache = {}

        def compressed(zz):
            key = zz.tobytes()
            if key not in cache:
                r, J = ls.residuals_and_jacobian(zz)
                gram, projected = J.T @ J, J.T @ r
                eigenvalues, vectors = np.linalg.eigh(gram)
                keep = eigenvalues > 1e-13 * max(float(eigenvalues[-1]), 1e-300)
                root = np.sqrt(eigenvalues[keep])
                n = J.shape[1]
                reduced, jacobian = np.zeros(n + 1), np.zeros((n + 1, n))
                reduced[: root.size] = (vectors[:, keep].T @ projected) / root
                jacobian[: root.size] = root[:, None] * vectors[:, keep].T
                reduced[n] = np.sqrt(max(float(r @ r) - float(reduced[:n] @ reduced[:n]), 0.0))
                cache.clear()
                cache[key] = (reduced, jacobian)
            return cache[key]

        result = least_squares(lambda zz: compressed(zz)[0], z, jac=lambda zz: compressed(zz)[1], bounds=(0.0, 1.0),
                               method="trf", x_scale="jac", ftol=self.tolerance, xtol=1e-10, gtol=1e-10,
                               max_nfev=self.max_iterations)
        return np.clip(result.x, 0.0, 1.0), int(result.nfev), f"least_squares: {_STATUS.get(result.status, result.message)}"

    def _fit_linear_variables(self, z):
        """Replace the start's stiffnesses and initial tensions by their bounded linear least-squares
        optimum for the start's geometry. The residual is exactly affine in them,
        ``r(z) = r(z0) + J_lin (z_lin - z0_lin)``, so one evaluation and one BVLS solve suffice.
        This keeps a start from wasting its budget on a stiffness guess off by orders of magnitude
        (and from stalling at k = 0, where the anchors have no gradient)."""
        z = self._feasible_free_lengths(z)
        linear = self.problem.model.linear_indices
        if not linear:
            return z
        r, J = self._ls.residuals_and_jacobian(z)
        columns = J[:, linear]
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
            if index is None:
                continue
            lengths = evaluation.lengths[:, column]
            spring_low, spring_high = spring.free_length_interval(lengths)
            low, high = max(lower[index], spring_low), min(upper[index], spring_high)
            if low <= high:
                value = float(np.clip(problem.scale(z)[index], low, high))
                z[index] = (value - lower[index]) / (upper[index] - lower[index])
        return np.clip(z, 0.0, 1.0)

    # ------------------------------------------------------------------ IPOPT
    def _nlpsol(self, nlp):
        options = {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes",
                   "ipopt.max_iter": self.max_iterations, "ipopt.tol": min(self.tolerance, 1e-8),
                   "ipopt.acceptable_tol": 1e-8, "ipopt.mu_strategy": "adaptive"}
        return ca.nlpsol("springbalance", "ipopt", {"x": nlp.z, "f": nlp.cost, "g": nlp.rows}, options)

    def _ipopt_solve(self, z, evaluation):
        problem = self.problem
        first_phase = problem.objective.first_phase
        if first_phase is None:
            if self._ipopt is None:
                self._nlp = problem.build()
                self._ipopt = self._nlpsol(self._nlp)
            return self._ipopt_run(self._ipopt, self._nlp, z, evaluation)
        # lexicographic: the first phase's optimum T*, then the objective's own NLP with its
        # epigraph variables bounded by T*·(1 + slack)
        if self._first is None:
            nlp = problem.build(first_phase)
            self._first = (nlp, self._nlpsol(nlp))
            self._nlp = problem.build()
            self._ipopt = self._nlpsol(self._nlp)
        z1, status1, iterations1 = self._ipopt_run(self._first[1], self._first[0], z, evaluation)
        first = problem.evaluate(problem.scale(z1))
        weighted = first.tau * problem.weights
        bound = problem.objective.phase_two_bound(first_phase.value(weighted, first.potential, problem.path_steps),
                                                  problem.torque_scale)
        upper = self._nlp.upper.copy()
        upper[self._nlp.n_design:] = bound
        z2, status2, iterations2 = self._ipopt_run(self._ipopt, self._nlp, z1, first, upper=upper)
        second = problem.evaluate(problem.scale(z2))
        value = problem.objective.value(second.tau * problem.weights, second.potential, problem.path_steps)
        kept = (second.max_violation <= max(FEASIBILITY_TOLERANCE, first.max_violation)
                and value <= (bound + EPIGRAPH_TOLERANCE) * problem.torque_scale)
        status = f"{status1}, then {status2.removeprefix('ipopt: ')}{'' if kept else ' (not kept)'}"
        return (z2 if kept else z1), status, iterations1 + iterations2

    def _ipopt_run(self, solver, nlp, z, evaluation, upper=None):
        problem = self.problem
        start = z
        if nlp.size > nlp.n_design:
            extra = nlp.extra_start(evaluation.tau * problem.weights)
            if upper is not None:
                extra = np.minimum(extra, upper[nlp.n_design:])
            start = np.concatenate([z, extra])
        solution = solver(x0=start, lbx=nlp.lower, ubx=nlp.upper if upper is None else upper, lbg=0.0, ubg=np.inf)
        stats = solver.stats()
        z_new = np.clip(np.array(solution["x"]).reshape(-1)[: nlp.n_design], 0.0, 1.0)
        return z_new, f"ipopt: {stats.get('return_status', 'unknown')}", int(stats.get("iter_count", 0))


class _LeastSquaresResiduals:
    """Scaled residuals ``r(z)`` and exact Jacobian ``dr/dz`` of a least-squares objective.

    One per-sample CasADi function of the *scaled* variables ``z`` gives the sample's
    residual rows and their transposed Jacobian, already scaled, so that the mapped,
    JIT-compiled evaluation lands in NumPy buffers that *are* ``r`` and ``J`` (no copies):

    - ``rms`` (and the warm-start phase of ``peak``/``energy``): ``w ⊙ tau / (S·sqrt(N·nv))``;
    - ``pe_variance``: the total potential over ``P·sqrt(N)``, centred here in NumPy;
    - constraint rows ``c / scale`` (≥ 0 when feasible) for the augmented Lagrangian, whose
      penalty rows ``max(0, λ - μ c)/√μ`` follow the objective rows when a penalty is set.
    """

    def __init__(self, problem):
        self.problem = problem
        self.variance = problem.objective.name == "pe_variance"
        model = problem.model
        lower, upper = problem.variables.bounds()
        n, nv = problem.workspace.size, problem.mechanism.nv
        blocks = model.constraint_blocks
        self.row_scale = np.array([block.scale for block in blocks]) if blocks else np.ones(0)
        self.n_sample_rows = n * len(blocks)
        self.bounds = (lower, upper)

        z = ca.SX.sym("z", problem.variables.size)
        data = ca.SX.sym("data", model.data_size)
        tau, potential, _, _, rows = model.sample(ca.DM(lower) + ca.DM(upper - lower) * z, data)
        if self.variance:
            residual = potential / (problem.potential_scale * np.sqrt(n))
        else:
            residual = tau * ca.DM(problem.weights / (problem.torque_scale * np.sqrt(n * nv)))
        scaled_rows = rows / ca.DM(self.row_scale) if blocks else rows
        function = ca.Function("scaled_residual", [z, data],
                               [residual, ca.jacobian(residual, z).T, scaled_rows, ca.jacobian(scaled_rows, z).T])
        self.function = compiled(function)
        self.evaluator = SampleEvaluator(self.function, problem.data)
        self.multipliers, self.penalty = None, 0.0
        self._last_z = None

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

    def _evaluate(self, z):
        if self._last_z is None or not np.array_equal(z, self._last_z):
            self.outputs = self.evaluator(z)
            self._last_z = np.array(z)
        return self.outputs

    def constraint_rows(self, z) -> np.ndarray:
        """Scaled constraint rows (N·n_c, then the linear rows), ≥ 0 when feasible."""
        matrix, offset = self._linear()
        return np.concatenate([self._evaluate(z)[2].reshape(-1), matrix @ z + offset])

    def residuals_and_jacobian(self, z):
        residual, jacobian, rows, row_jacobian = self._evaluate(z)
        n_x = jacobian.shape[2]
        r, J = residual.reshape(-1), jacobian.reshape(-1, n_x)
        if self.variance:  # centre the potential (per scenario block): r_i - mean(r), J_i - mean(J)
            blocks = self.problem.model.n_scenarios
            r = (r.reshape(blocks, -1) - r.reshape(blocks, -1).mean(axis=1, keepdims=True)).reshape(-1)
            J = (J.reshape(blocks, -1, n_x) - J.reshape(blocks, -1, n_x).mean(axis=1, keepdims=True)).reshape(-1, n_x)
        if self.multipliers is None:
            return r, J
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
