"""The scaled residuals of a least-squares objective and their exact Jacobian, summed block by block
(:class:`_LeastSquaresResiduals`)."""

from __future__ import annotations

import copy
from typing import Iterator

import casadi as ca
import numpy as np

from springbalance.design.solvers.records import Problem
from springbalance.design.torque_model.compilation import compiled
from springbalance.design.torque_model.evaluators import BlockEvaluator


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

    def __init__(self, problem: Problem, block: int | None = None) -> None:
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
        function = ca.Function(
            "scaled_residual",
            [z, data],
            [
                residual,
                ca.densify(ca.jacobian(residual[: self.n_moving], z).T),
                scaled_rows,
                ca.jacobian(scaled_rows, z).T,
            ],
        )
        self.function = compiled(function)
        self.evaluator = BlockEvaluator(self.function, problem.data, block)
        self.multipliers: np.ndarray | None = None
        self.penalty = 0.0
        # the sample constraint rows at _rows_z
        self._rows_z: np.ndarray | None = None
        self._rows: np.ndarray | None = None
        # (z, penalty, multipliers) → (JᵀJ, Jᵀr, rᵀr)
        self._normal_key: tuple[bytes, float, bytes | None] | None = None
        self._normal: tuple[np.ndarray, np.ndarray, float] | None = None
        # z → full outputs (residuals_and_jacobian)
        self._full_z: np.ndarray | None = None
        self._full: list[np.ndarray] | None = None

    def for_problem(self, problem: Problem) -> _LeastSquaresResiduals:
        """These compiled residuals bound to ``problem`` (a copy of theirs with other linear rows), with no
        penalty: multipliers set for the other problem count its linear rows, not ``problem``'s."""
        bound = copy.copy(self)
        bound.problem = problem
        bound.set_penalty(None, 0.0)
        bound._normal_key, bound._normal = None, None
        return bound

    def set_penalty(self, multipliers: np.ndarray | None, penalty: float) -> None:
        """Penalty rows ``max(0, λ - μ c)/√μ`` with ``λ = multipliers``, ``μ = penalty`` from now on (None: none)."""
        self.multipliers, self.penalty = multipliers, penalty

    def _linear(self) -> tuple[np.ndarray, np.ndarray]:
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
    def _blocks(self, z: np.ndarray) -> Iterator[tuple[int, int, list[np.ndarray]]]:
        """The evaluator's blocks at ``z``; records the sample constraint rows on the way."""
        z = np.array(z, dtype=float)
        rows_all = np.empty(self.n_sample_rows)
        n_c = self.row_scale.size
        for start, stop, outputs in self.evaluator.blocks(z):
            if n_c:
                rows_all[start * n_c : stop * n_c] = outputs[2].reshape(-1)
            yield start, stop, outputs
        self._rows_z, self._rows = z, rows_all

    def constraint_rows(self, z: np.ndarray) -> np.ndarray:
        """Scaled constraint rows (N·n_c, then the linear rows), ≥ 0 when feasible."""
        if self._rows_z is None or not np.array_equal(z, self._rows_z):
            for _ in self._blocks(z):
                pass
        assert self._rows is not None  # recorded by the pass over the blocks
        matrix, offset = self._linear()
        return np.concatenate([self._rows, matrix @ z + offset])

    def normal_equations(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        """``(JᵀJ, Jᵀr, rᵀr)`` of the residual (with the penalty rows when a penalty is set) at ``z``,
        summed block by block."""
        key = (
            np.array(z, dtype=float).tobytes(),
            self.penalty,
            None if self.multipliers is None else np.asarray(self.multipliers).tobytes(),
        )
        if self._normal_key == key and self._normal is not None:  # (set together)
            return self._normal
        if self.variance:
            r, J = self.residuals_and_jacobian(z)
            normal = (J.T @ J, J.T @ r, float(r @ r))
        else:
            normal = self._accumulate(np.array(z, dtype=float))
        self._normal_key, self._normal = key, normal
        return normal

    def _accumulate(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        n_x = self.problem.variables.size
        n_c = self.row_scale.size
        gram, projected, squares = np.zeros((n_x, n_x)), np.zeros(n_x), 0.0
        penalised = self.multipliers is not None
        if penalised:
            root = np.sqrt(self.penalty)
            multipliers = np.asarray(self.multipliers)
        for start, stop, (residual, jacobian, rows, row_jacobian) in self._blocks(z):
            r, J = residual.reshape(-1), jacobian.reshape(-1, n_x)
            moving = (
                r
                if self.n_moving == self.order.size
                else residual.reshape(-1, self.order.size)[:, : self.n_moving].reshape(-1)
            )
            gram += J.T @ J
            projected += J.T @ moving
            squares += float(r @ r)
            if penalised and n_c:
                shifted = multipliers[start * n_c : stop * n_c] - self.penalty * rows.reshape(-1)
                active = shifted > 0
                if np.any(active):
                    penalty_r = shifted[active] / root
                    penalty_J = -root * row_jacobian.reshape(-1, n_x)[active]
                    gram += penalty_J.T @ penalty_J
                    projected += penalty_J.T @ penalty_r
                    squares += float(penalty_r @ penalty_r)
        matrix, offset = self._linear()
        if penalised and offset.size:
            shifted = multipliers[self.n_sample_rows :] - self.penalty * (matrix @ z + offset)
            active = shifted > 0
            penalty_r = shifted[active] / root
            penalty_J = -root * matrix[active]
            gram += penalty_J.T @ penalty_J
            projected += penalty_J.T @ penalty_r
            squares += float(penalty_r @ penalty_r)
        return gram, projected, squares

    def linear_columns(self, z: np.ndarray, columns: list[int]) -> tuple[np.ndarray, np.ndarray]:
        """The objective residual ``r`` (no penalty rows) and the columns ``columns`` of its Jacobian at ``z``."""
        if self.variance:
            rows, jacobian = self._objective_rows(z)
            return rows, jacobian[:, columns]
        per_sample = self.order.size
        r: np.ndarray | None = None
        J: np.ndarray | None = None
        for start, stop, (residual, jacobian, _, _) in self._blocks(z):
            if r is None or J is None:
                r = np.empty(self.evaluator.n_samples * per_sample)
                J = np.empty((r.size, len(columns)))
            r_block, J_block = self._in_row_order(residual, jacobian)
            r[start * per_sample : stop * per_sample] = r_block
            J[start * per_sample : stop * per_sample] = J_block[:, columns]
        if r is None or J is None:
            raise ValueError("no samples to evaluate")
        return r, J

    def _in_row_order(self, residual: np.ndarray, jacobian: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
    def _full_outputs(self, z: np.ndarray) -> list[np.ndarray]:
        """Every output for all samples at ``z`` (``(N, cols, rows)`` arrays, as SampleEvaluator's)."""
        if self._full_z is None or not np.array_equal(z, self._full_z):
            self._full = self.evaluator.evaluate(np.array(z, dtype=float))
            self._full_z = np.array(z)
        assert self._full is not None  # set with _full_z
        return self._full

    def _objective_rows(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        residual, jacobian, _, _ = self._full_outputs(z)
        n_x = self.problem.variables.size
        r, J = self._in_row_order(residual, jacobian)
        if self.variance:  # centre the potential (per scenario block): r_i - mean(r), J_i - mean(J)
            blocks = self.problem.model.n_scenarios
            r = (r.reshape(blocks, -1) - r.reshape(blocks, -1).mean(axis=1, keepdims=True)).reshape(-1)
            J = (J.reshape(blocks, -1, n_x) - J.reshape(blocks, -1, n_x).mean(axis=1, keepdims=True)).reshape(-1, n_x)
        return r, J

    def residuals_and_jacobian(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
