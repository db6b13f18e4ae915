"""When a start's least squares hands over to IPOPT (:meth:`_MultiStartSolver._cold`): a design left outside its
rows, and a run that stopped on its step size with penalty rows in the residual (a stall at a penalty row's kink,
not a stationary design); and when the polish goes on with a start (:mod:`springbalance.design.solvers.polish`)."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from springbalance.design.solvers import solve_problem
from springbalance.design.solvers.least_squares import STEP_SIZE_STOP
from springbalance.design.solvers.multistart import _MultiStartSolver
from springbalance.io.config import config_from_dict


@pytest.fixture(scope="module")
def coils():
    """The demo's coils with their static rules (constraint rows: penalty rows in least squares) and a feasible
    design of them."""
    record = yaml.safe_load(open("examples/two_link.yaml", encoding="utf-8"))
    for spring in record["springs"]:
        spring.pop("duty", None)
    problem = config_from_dict(record, base_dir=Path("examples")).problem
    solution = solve_problem(problem, starts=1, seed=0, progress=False)
    assert problem.evaluate(solution.x).max_violation <= 1e-6
    return problem, np.asarray(solution.x, dtype=float)


def _cold_after(problem, x, status):
    """``_cold`` from ``x`` with least squares replaced by a run that ends at ``x`` with ``status``."""
    solver = _MultiStartSolver(problem, "auto", 200, 1e-8)
    assert solver._residuals().n_constraint_rows > 0
    z = problem.unscale(x)
    solver._least_squares = lambda *args, **kwargs: (z.copy(), status, 7, None)
    return solver._cold(z, False)


def test_a_step_size_stop_with_penalty_rows_goes_on_with_ipopt(coils):
    problem, x = coils
    _, status, iterations, lam_g, _ = _cold_after(problem, x, STEP_SIZE_STOP)
    assert status.startswith("ipopt:")
    assert iterations > 7 and lam_g is not None


@pytest.mark.parametrize(
    "status", ["least_squares: converged (cost change)", "least_squares: converged (cost change and step size)"]
)
def test_a_feasible_design_that_least_squares_converged_on_is_kept(coils, status):
    problem, x = coils
    z, kept, iterations, lam_g, _ = _cold_after(problem, x, status)
    assert kept == status and iterations == 7 and lam_g is None
    np.testing.assert_array_equal(z, problem.unscale(x))


def test_a_promising_start_that_the_polish_brought_close_to_its_rules_is_polished_again(monkeypatch):
    """The demo's coils with 40 iterations a start and a polish: start 3 stops at 1.87 N·m, 0.56 outside its rules,
    below the only feasible start (2.77). One polish takes it to 5.8e-4 outside (still stopped by the budget); the
    next one finishes it feasible at 1.81. Without the further polish the multi-start keeps 2.77."""
    from springbalance.design.solvers import polish

    record = yaml.safe_load(open("examples/two_link.yaml", encoding="utf-8"))
    problem = config_from_dict(record, base_dir=Path("examples")).problem

    def solved():
        solution = solve_problem(problem, starts=4, seed=0, progress=False, max_iterations=40, polish_iterations=40)
        return problem.objective_value(problem.evaluate(solution.x)), solution

    again, solution = solved()
    monkeypatch.setattr(polish, "REPOLISHES", 0)
    once, _ = solved()
    assert again < 0.75 * once
    polished = [start for start in solution.starts if "polished after" in start.status]
    assert polished and all(start.feasible for start in polished)
    assert min(start.iterations for start in polished) > 2 * 40  # screened, then polished twice
