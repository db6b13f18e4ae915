"""When a start's least squares hands over to IPOPT (:meth:`_MultiStartSolver._cold`): a design left outside its
rows, and a run that stopped on its step size with penalty rows in the residual (a stall at a penalty row's kink,
not a stationary design); and when the polish goes on with a start, or starts it again, cold
(:mod:`springbalance.design.solvers.polish`)."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from springbalance.design.solvers import solve_problem
from springbalance.design.solvers.least_squares import STEP_SIZE_STOP
from springbalance.design.solvers.multistart import _MultiStartSolver
from springbalance.design.solvers.records import StartRecord
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


class _ScriptedRunner:
    """A start runner whose continued starts are given in advance, call by call (the polish's own logic is what
    is tested: which starts it continues, how often, and which record it keeps)."""

    def __init__(self, answers):
        self.answers, self.calls, self.cold = list(answers), [], []
        self.solver = type("Solver", (), {"max_iterations": None})()

    def run(self, tasks):
        self.calls.append([index for index, *_ in tasks])
        # a cold start prepares its design (least squares first) and has no multipliers to go on from
        self.cold.append([prepare and multipliers is None for _, _, prepare, multipliers in tasks])
        return [self.answers.pop(0)(index) for index, *_ in tasks]


class _Problem:
    """What the polish reads of a problem: its scaling (the identity here) and a single-phase objective."""

    objective = type("Objective", (), {"first_phase": None})()

    @staticmethod
    def unscale(z):
        return z


def _record(index, objective, violation, status, iterations=40):
    return StartRecord(index, np.zeros(2), np.full(2, objective), objective, violation, status, iterations, 0.0)


def _promising_case(second_violation):
    """The demo's coils at 40 iterations a start, as one machine ran them: start 0 feasible at 2.77 N·m; start 3
    stopped by its budget at 1.87 N·m, 0.56 outside its rules. Its first polish stops on the budget again at 1.85,
    ``second_violation`` outside; a second one finishes it feasible at 1.81."""
    stopped = "ipopt: Maximum_Iterations_Exceeded"
    records = [_record(0, 2.77, 0.0, "ipopt: Solve_Succeeded"), _record(3, 1.87, 0.56, stopped)]
    runner = _ScriptedRunner(
        [
            lambda index: _record(index, 1.85, second_violation, stopped),
            lambda index: _record(index, 1.81, 0.0, "ipopt: Solve_Succeeded"),
        ]
    )
    return records, runner


def test_a_promising_start_that_the_polish_brought_close_to_its_rules_is_polished_again(monkeypatch):
    """The first polish cut start 3's violation from 0.56 to 5.8e-4 (below a quarter) and stopped on its budget
    below the best feasible objective: it is polished again and wins (1.81 against 2.77). Without the further
    polishes the multi-start keeps 2.77. (The demo's own run of this case depends on the processor's floating-point
    path: on an AMD EPYC the first polish already finishes the start, so the logic is tested on scripted runs.)"""
    from springbalance.design.solvers import polish

    records, runner = _promising_case(5.8e-4)
    best = polish.polished_best(_Problem(), runner, records, 40, 4)
    assert best.index == 3 and best.objective == 1.81
    assert runner.calls == [[3], [3]] and runner.solver.max_iterations == 40
    assert best.status.endswith("(polished after 80 iterations)") and best.iterations == 120
    monkeypatch.setattr(polish, "REPOLISHES", 0)
    records, runner = _promising_case(5.8e-4)
    assert polish.polished_best(_Problem(), runner, records, 40, 4).objective == 2.77
    assert runner.calls == [[3]]


def test_a_polish_that_closes_in_slowly_is_not_repeated():
    """A first polish that only halved the violation (0.56 to 0.28: more than a quarter) is not repeated."""
    from springbalance.design.solvers import polish

    records, runner = _promising_case(0.28)
    assert polish.polished_best(_Problem(), runner, records, 40, 4).objective == 2.77
    assert runner.calls == [[3]]


def _stuck_case(restarted_violation):
    """ur5-coils at seed 0 on an AMD EPYC machine: every start stopped on its budget 5e-4 to 1.5e-3 outside its
    rules near 0.39 N·m (start 3 far outside), and their polish left them there. Started again, cold, from where it
    left them, the least violated (start 1) ends ``restarted_violation`` outside at 0.394 N·m, the others still
    outside."""
    stopped = "ipopt: Maximum_Iterations_Exceeded"
    violations = {0: 1.48e-3, 1: 5.1e-4, 2: 1.13e-3, 3: 920.7}
    records = [_record(i, 0.40 if i < 3 else 234.0, v, stopped, iterations=100) for i, v in violations.items()]
    runner = _ScriptedRunner(
        [lambda index: _record(index, 0.40, 0.9 * violations[index], f"{stopped} (polished)")] * 3
        + [
            lambda index: (
                _record(index, 0.394, restarted_violation, "least_squares: converged (cost change)")
                if index == 1
                else _record(index, 0.40, violations[index], stopped)
            )
        ]
        * 3
    )
    return records, runner


def test_starts_that_no_polish_made_feasible_start_again_cold_from_where_it_left_them():
    from springbalance.design.solvers import polish

    records, runner = _stuck_case(0.0)
    best = polish.polished_best(_Problem(), runner, records, 400, 4)
    assert best.index == 1 and best.feasible and best.objective == 0.394
    assert best.status == "least_squares: converged (cost change) (restarted after 140 iterations)"
    # the three least violated, polished (warm), then started again (cold), least violated first; start 3 neither
    assert runner.calls == [[1, 2, 0], [1, 2, 0]]
    assert runner.cold == [[False, False, False], [True, True, True]]


def test_a_cold_start_again_that_stays_outside_the_rules_is_still_no_design():
    from springbalance.design.solvers import polish
    from springbalance.errors import SolverError

    records, runner = _stuck_case(2e-4)
    with pytest.raises(SolverError, match="no start gave a feasible design") as caught:
        polish.polished_best(_Problem(), runner, records, 400, 4)
    assert "(restarted after 140 iterations), violation 0.0002" in str(caught.value)
    assert runner.calls == [[1, 2, 0], [1, 2, 0]]
