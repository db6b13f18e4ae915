"""Augmented-Lagrangian least squares for one start (:class:`LeastSquaresStarts`), and :func:`refine`.

SciPy's bounded trust-region-reflective method works on an equivalent *compressed* residual of n+1 rows
(n ≈ 30 variables, while the residual has N·nv ≈ 25,000 rows), see :meth:`LeastSquaresStarts._trust_region`.
Practical constraints (tension, stretch, force, length) enter through an augmented Lagrangian: penalty rows
``max(0, λ - μ c)/√μ`` join the residual and the multipliers are updated between runs. A start is prepared
first: free lengths moved into the interval the start's spring lengths allow, and the variables the torque
is linear in (stiffness, initial tension) set to their bounded linear least-squares optimum. After a warm
IPOPT solve, :meth:`LeastSquaresStarts._exact_polish` gives Gauss–Newton a few iterations from IPOPT's
design: where the residual can vanish (exact balance) it ends at round-off instead of IPOPT's tolerance.
"""

from __future__ import annotations

import numpy as np
from threadpoolctl import threadpool_limits

from springbalance.design.solvers.auxiliary import tight_bounds
from springbalance.design.solvers.records import FEASIBILITY_TOLERANCE, Problem
from springbalance.design.solvers.residuals import _LeastSquaresResiduals

#: augmented-Lagrangian rounds of a start, and of a problem with auxiliary variables (a coil's fatigue bounds
#: ``F_lo ≤ P_i ≤ F_hi``, docs/model.md §3.8.2): rows that tie every sample's force to one variable, which
#: Gauss–Newton on penalty rows closes only slowly (on the demo every round ended on the iteration limit, 2 to 4 of
#: them per start, and IPOPT finished each start anyway). Such a start hands over to IPOPT after its first round.
AL_ROUNDS, AUXILIARY_AL_ROUNDS = 12, 1

_STATUS = {
    -1: "improper input",
    0: "iteration limit reached",
    1: "converged (gradient)",
    2: "converged (cost change)",
    3: "converged (step size)",
    4: "converged (cost change and step size)",
}
#: the status of a run that SciPy stopped on its step size alone (``xtol``)
STEP_SIZE_STOP = f"least_squares: {_STATUS[3]}"


#: Gauss–Newton iterations that try to take a warm IPOPT design of a least-squares objective to round-off ...
POLISH_ITERATIONS = 20
#: ... kept when its objective falls below this fraction of IPOPT's [1]
POLISH_GAIN = 0.5


class LeastSquaresStarts:
    """The least-squares part of :class:`~springbalance.design.solvers.multistart._MultiStartSolver` (a mixin):
    it reads ``problem``, ``fixed``, ``max_iterations``, ``tolerance`` and keeps ``_ls`` (the residual)."""

    problem: Problem
    fixed: np.ndarray
    max_iterations: int
    tolerance: float
    _ls: _LeastSquaresResiduals | None

    def _least_squares(
        self, z0: np.ndarray, prepare: bool = True, multipliers: np.ndarray | None = None, budget: int | None = None
    ) -> tuple[np.ndarray, str, int, np.ndarray | None]:
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
        z = tight_bounds(self.problem, z)  # a coil's fatigue bounds at the start's force range
        multipliers = np.zeros(ls.n_constraint_rows) if multipliers is None else np.asarray(multipliers, dtype=float)
        penalty, iterations, status = 10.0, 0, "least_squares: not run"
        previous_violation = np.inf
        rounds = AUXILIARY_AL_ROUNDS if self.problem.model.auxiliary_names else AL_ROUNDS
        for _ in range(rounds if ls.n_constraint_rows else 1):
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

    def _residuals(self) -> _LeastSquaresResiduals:
        problem = self.problem
        if self._ls is None:  # compiled once per problem, kept across solves (the fit loop re-solves)
            if problem.least_squares_cache is None:
                problem.least_squares_cache = _LeastSquaresResiduals(problem)
            self._ls = problem.least_squares_cache
        return self._ls

    def _trust_region(
        self, ls: _LeastSquaresResiduals, z: np.ndarray, budget: int | None = None
    ) -> tuple[np.ndarray, int, str]:
        """SciPy's bounded trust-region-reflective least squares on the *compressed* residual.

        With ``JᵀJ = V Λ Vᵀ`` and ``R = Λ^½ Vᵀ``, ``q = Λ^-½ Vᵀ Jᵀ r`` (directions with
        ``λ ≤ 1e-13 λ_max`` dropped) and ``ρ² = |r|² - |q|²``, the residual ``(q, ρ)`` with
        Jacobian ``[R; 0]`` has the same norm and the same Gauss–Newton model,
        ``|r + J δ|² = |q + R δ|² + ρ²``, as the full one. The solver's iterates are unchanged
        while its linear algebra shrinks from N·nv rows to n+1 (the Gram matrix ``JᵀJ`` and ``Jᵀr``
        are summed over blocks of samples, :meth:`_LeastSquaresResiduals.normal_equations`).
        """
        from scipy.optimize import least_squares  # imported when first used: SciPy's optimize costs 0.2 s at start-up

        cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
        held = self.fixed.any()
        free = ~self.fixed
        full = z.copy()

        def compressed(zz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            key = zz.tobytes()
            if key not in cache:
                if held:  # the held variables' columns left out
                    full[free] = zz
                    gram, projected, squares = ls.normal_equations(full)  # summed over blocks of samples
                    gram, projected = gram[np.ix_(free, free)], projected[free]
                else:
                    gram, projected, squares = ls.normal_equations(zz)  # summed over blocks of samples
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

        result = least_squares(
            lambda zz: compressed(zz)[0],
            z[free],
            jac=lambda zz: compressed(zz)[1],
            bounds=(0.0, 1.0),
            method="trf",
            x_scale="jac",
            ftol=self.tolerance,
            xtol=1e-10,
            gtol=1e-10,
            max_nfev=self.max_iterations if budget is None else budget,
        )
        full[free] = np.clip(result.x, 0.0, 1.0)
        return full, int(result.nfev), f"least_squares: {_STATUS.get(result.status, result.message)}"

    def _fit_linear_variables(self, z: np.ndarray) -> np.ndarray:
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
        r, columns = self._residuals().linear_columns(z, linear)
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

    def _feasible_free_lengths(self, z: np.ndarray) -> np.ndarray:
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

    def _exact_polish(
        self, z: np.ndarray, status: str, iterations: int, lam_g: np.ndarray | None
    ) -> tuple[np.ndarray, str, int, np.ndarray | None]:
        """IPOPT's design ``z`` of a least-squares objective, or a design that Gauss–Newton (an augmented-Lagrangian
        run of :data:`POLISH_ITERATIONS`, from IPOPT's multipliers) takes from it to an objective below
        :data:`POLISH_GAIN` of IPOPT's, within the rows: a residual that can vanish (exact balance) ends at
        round-off, not at IPOPT's tolerance; any other design stays IPOPT's."""
        problem = self.problem
        if lam_g is None or not problem.objective.least_squares or "Solve_Succeeded" not in status:
            return z, status, iterations, lam_g
        before = problem.objective_value(problem.evaluate(problem.scale(z)))
        ls = self._residuals()
        start = 0.5 * problem.scaled_row_multipliers(-lam_g, ls.n_constraint_rows - ls.n_sample_rows)
        polished, _, more, _ = self._least_squares(z, False, start, POLISH_ITERATIONS)
        evaluation = problem.evaluate(problem.scale(polished))
        violation = max(evaluation.max_violation, problem.linear_violation(evaluation.x))
        if violation > FEASIBILITY_TOLERANCE or not (problem.objective_value(evaluation) < POLISH_GAIN * before):
            return z, status, iterations + more, lam_g
        return (
            polished,
            f"{status}; least squares to {problem.objective_value(evaluation):.3g}",
            iterations + more,
            None,
        )


def refine(problem: Problem, x: np.ndarray, iterations: int = 8) -> np.ndarray:
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
