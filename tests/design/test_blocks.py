"""JᵀJ and Jᵀr summed over blocks of samples: the numbers of the full Jacobian, without it."""

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.solvers.residuals import _LeastSquaresResiduals
from springbalance.design.torque_model import BlockEvaluator, SampleEvaluator

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def problem():
    mechanism = sb.Mechanism.from_urdf(ROOT / "urdf" / "two_link_planar.urdf")
    springs = [
        sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free([-0.2, 0, 0], [0.2, 0, 0.3])),
            sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.5, 0, 0])),
            stiffness=sb.Free(0, 2000),
            free_length=sb.Free(0.02, 0.5),
            max_stretch=2.0,
        ),
        sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free([-0.3, 0, -0.1], [0.3, 0, 0.6])),
            sb.Anchor("link2", sb.Free([0.02, 0, 0], [0.4, 0, 0])),
            stiffness=sb.Free(0, 2000),
            free_length=sb.Free(0.02, 0.5),
        ),
    ]
    return sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, 203, seed=5), springs)


def _full(residuals, z):
    """The reference: one block of all samples, J materialised."""
    return residuals.residuals_and_jacobian(z)


@pytest.mark.parametrize("block", [1, 7, 64, 203, 1000])
def test_blocked_normal_equations_equal_the_full_jacobians(problem, block):
    reference = _LeastSquaresResiduals(problem, block=problem.workspace.size)
    blocked = _LeastSquaresResiduals(problem, block=block)
    assert blocked.evaluator.block == min(block, problem.workspace.size)
    rng = np.random.default_rng(block)
    for penalised in (False, True):
        z = rng.random(problem.variables.size)
        multipliers = None
        if penalised:  # multipliers that make part of the rows active
            multipliers = np.where(rng.random(reference.constraint_rows(z).size) < 0.5, 0.3, 0.0)
        for residuals in (reference, blocked):
            residuals.set_penalty(multipliers, 10.0 if penalised else 0.0)
        r, J = _full(reference, z)
        gram, projected, squares = blocked.normal_equations(z)
        assert np.allclose(gram, J.T @ J, rtol=1e-12, atol=1e-12 * np.abs(J.T @ J).max())
        assert np.allclose(projected, J.T @ r, rtol=1e-12, atol=1e-12 * np.abs(J.T @ r).max())
        assert squares == pytest.approx(float(r @ r), rel=1e-12)
        assert np.array_equal(blocked.constraint_rows(z), reference.constraint_rows(z))
        if penalised:
            assert np.any(r[problem.workspace.size * problem.mechanism.nv :] != 0)  # penalty rows took part


def test_linear_columns_are_the_full_jacobians_columns(problem):
    residuals = _LeastSquaresResiduals(problem, block=10)
    z = np.full(problem.variables.size, 0.4)
    residuals.set_penalty(None, 0.0)
    r, J = residuals.residuals_and_jacobian(z)
    columns = problem.model.linear_indices
    r_lin, J_lin = residuals.linear_columns(z, columns)
    assert np.array_equal(r_lin, r) and np.array_equal(J_lin, J[:, columns])


def test_block_evaluator_reads_the_data_in_place(problem):
    assert problem.data.flags.f_contiguous  # each sample's column is contiguous: blocks are views
    evaluator = BlockEvaluator(problem.model.sample, problem.data, block=50)
    whole = SampleEvaluator(problem.model.sample, problem.data)
    x = problem.scale(np.full(problem.variables.size, 0.3))
    assert np.shares_memory(evaluator._data, problem.data) and np.shares_memory(whole._data, problem.data)
    for blocked, full in zip(evaluator.evaluate(x), whole(x)):
        assert np.array_equal(blocked, full)
    numeric = problem.model.evaluate(x, problem.data)  # CasADi's own call on all samples
    evaluation = problem.evaluate(x)
    assert np.array_equal(evaluation.tau, numeric["tau"]) and np.array_equal(evaluation.constraint_rows, numeric["C"])


def test_rows_no_variable_moves_are_left_out_of_the_jacobian():
    """A shoulder spring alone: the elbow's residual row is constant in z (the link1 anchor's Jacobian
    column of the elbow is zero at every sample). The solver's sums leave it out of J, keep it in rᵀr,
    and the full r is the weighted, scaled residual torque of every joint."""
    mechanism = sb.Mechanism.from_urdf(ROOT / "urdf" / "two_link_planar.urdf")
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.2, 0, 0], [0.2, 0, 0.3])),
        sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.5, 0, 0])),
        stiffness=sb.Free(0, 2000),
        free_length=sb.Free(0.02, 0.5),
    )
    problem = sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, 97, seed=2), [spring])
    residuals = _LeastSquaresResiduals(problem, block=10)
    assert residuals.n_moving == 1 and residuals.order.tolist() == [0, 1]
    z = np.full(problem.variables.size, 0.6)
    r, J = residuals.residuals_and_jacobian(z)
    n, nv = problem.workspace.size, mechanism.nv
    tau = problem.evaluate(problem.scale(z)).tau
    assert np.allclose(r, (tau * problem.weights / (problem.torque_scale * np.sqrt(n * nv))).reshape(-1), rtol=1e-12)
    assert np.all(J.reshape(n, nv, -1)[:, 1] == 0) and np.any(J.reshape(n, nv, -1)[:, 0] != 0)
    gram, projected, squares = residuals.normal_equations(z)
    assert np.allclose(gram, J.T @ J, rtol=1e-12) and np.allclose(projected, J.T @ r, rtol=1e-12)
    assert squares == pytest.approx(float(r @ r), rel=1e-12)
    assert float(r.reshape(n, nv)[:, 1] @ r.reshape(n, nv)[:, 1]) > 0  # the elbow row (gravity alone) is in rᵀr
