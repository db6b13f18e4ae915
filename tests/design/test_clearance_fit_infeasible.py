"""A fitting round of the clearance loop that stops infeasible is never the fit's design (issue 27).

The arm and springs are those of tests/design/test_clearance_constraint.py (two-link planar arm with
collision boxes, a ground→link1 and a link1→link2 zero-free-length spring whose anchors may leave the
arm's plane by 0.1 m). The fit starts from the in-plane optimum, whose first spring passes through link2.

IPOPT stopping a round infeasible is made deterministic here: the solver of the rounds is wrapped so that
its first rounds raise the :class:`SolverError` IPOPT's infeasible stop raises, carrying as least
violating iterate a design that is clear of the arm (every anchor 0.1 m out of the arm's plane, where the
0.04 m thick links cannot reach a 0.01 m capsule) but breaks a bound: the first spring's stiffness is
-50 N/m, below its bound 0. Before the fix, the loop found that design clear and returned it as
converged.
"""

from __future__ import annotations

import numpy as np
import pytest

import springbalance as sb
from clearance_helpers import crossing_case
from springbalance.design import clearance_round
from springbalance.design.clearance import FitRecord
from springbalance.design.clearance_fit import fit_to_arm
from springbalance.design.clearance_starts import fit_from_starts
from springbalance.design.solvers import Solution
from springbalance.design.solvers.records import StartRecord
from springbalance.errors import SolverError

OPTIONS = {"method": "auto", "max_iterations": 100, "tolerance": 1e-8, "polish_iterations": None}
MARGIN = 0.005


@pytest.fixture(scope="module")
def problem():
    return crossing_case(MARGIN)


def broken(problem: sb.DesignProblem, x: np.ndarray) -> np.ndarray:
    """``x`` with every anchor 0.1 m out of the arm's plane (clear of it) and s1's stiffness -50 N/m."""
    names = problem.variables.names
    out = np.array(x, dtype=float)
    for index, name in enumerate(names):
        if name.endswith(".y"):
            out[index] = 0.1
    out[names.index("s1.stiffness")] = -50.0
    return out


def trusted(problem: sb.DesignProblem) -> bool:
    """Whether ``problem`` is a round's attempt inside its trust region (clearance_round.trust_rows)."""
    rows = problem.linear_rows
    return rows is not None and any("within its trust region" in label for label in rows.labels)


def stopping(monkeypatch: pytest.MonkeyPatch, rounds: int, inside: list | None = None) -> list[np.ndarray]:
    """Make the first ``rounds`` solves of fitting rounds stop infeasible; returns the iterates they reported
    (``inside``: also collects those of the attempts inside a trust region)."""
    real = clearance_round.solve_problem
    reported: list[np.ndarray] = []

    def solve(problem: sb.DesignProblem, **options):
        if len(reported) >= rounds:
            return real(problem, **options)
        x = broken(problem, options["initial"])
        reported.append(x)
        if inside is not None and trusted(problem):
            inside.append(x)
        objective = float(problem.objective_value(problem.evaluate(x)))
        record = StartRecord(0, x, x, objective, 50.0, "ipopt: Infeasible_Problem_Detected", 12, 0.0)
        raise SolverError("no start met the rows", problem, [record])

    monkeypatch.setattr(clearance_round, "solve_problem", solve)
    return reported


def within_bounds(problem: sb.DesignProblem, x: np.ndarray) -> bool:
    lower, upper = np.array(problem.variables.lower), np.array(problem.variables.upper)
    return bool(np.all(x >= lower - 1e-9) and np.all(x <= upper + 1e-9))


def test_the_broken_design_is_clear_and_out_of_bounds(problem):
    """The premise: the reported iterate would pass the clearance check, yet it is no design."""
    fitted, start = problem
    x = broken(fitted, start)
    assert not within_bounds(fitted, x)
    for row in sb.DesignResult(fitted, x).clearance(samples=256).rows:
        assert row.distance >= MARGIN


def test_a_round_that_stops_infeasible_is_not_returned(problem, monkeypatch):
    """One round stops infeasible; the loop goes on from its iterate and returns a design within bounds."""
    fitted, start = problem
    reported = stopping(monkeypatch, 1)
    solution, fit, rows = fit_to_arm(fitted, Solution(start, [], "auto", 0, "given"), **OPTIONS)
    assert len(reported) == 1
    assert not np.allclose(solution.x, reported[0])
    assert within_bounds(fitted, solution.x)
    assert rows.evaluate(solution.x).max_violation <= 1e-6
    if fit.converged:
        for row in sb.DesignResult(fitted, solution.x, fit=fit).clearance(samples=256).rows:
            assert row.distance >= MARGIN


def test_rounds_that_keep_stopping_fall_back_and_say_not_converged(problem, monkeypatch):
    """Every round stops infeasible: the fit falls back to the start (round 0, through link2) and is not
    converged, and says so. The loop ran twice, the second time with a trust region (each of its rounds tried
    inside it, then without it), and each run gave up after INFEASIBLE_ROUNDS rounds."""
    fitted, start = problem
    inside: list[np.ndarray] = []
    reported = stopping(monkeypatch, 10**6, inside)
    solution, fit, rows = fit_to_arm(fitted, Solution(start, [], "auto", 0, "given"), **OPTIONS)
    assert len(inside) == clearance_round.INFEASIBLE_ROUNDS
    assert len(reported) - len(inside) == 2 * clearance_round.INFEASIBLE_ROUNDS
    assert fit.rounds == 2 * clearance_round.INFEASIBLE_ROUNDS
    assert not fit.converged
    np.testing.assert_array_equal(solution.x, start)
    assert rows.linear_rows is None  # the start's problem: no rows yet
    assert "fell back to the design of round 0" in solution.status and "NOT converged" in solution.status


def test_the_fit_moves_on_to_the_next_start_when_the_first_one_fails(problem, monkeypatch):
    """clearance.starts = 1, the best start's rounds stop infeasible: the next ranked design of the
    multi-start is fitted (with the real solver) and its converged fit is the answer."""
    fitted, start = problem
    second = np.array(start)
    names = fitted.variables.names
    for index, name in enumerate(names):
        if name.endswith(".y"):
            second[index] = 0.05 if name.startswith("s1") else -0.05  # out of the plane, each on its side
    records = [
        StartRecord(
            i, x, x, float(fitted.objective_value(fitted.evaluate(x))) + i, 0.0, "ipopt: Solve_Succeeded", 9, 0.0
        )
        for i, x in enumerate([start, second])
    ]
    stopping(monkeypatch, clearance_round.INFEASIBLE_ROUNDS)
    solution, fit, rows = fit_from_starts(fitted, Solution(start, records, "auto", 0, "given"), **OPTIONS)
    assert fit.starts == 2 and fit.converged
    assert within_bounds(fitted, solution.x)
    assert rows.evaluate(solution.x).max_violation <= 1e-6
    for row in sb.DesignResult(fitted, solution.x, fit=fit).clearance(samples=256).rows:
        assert row.distance >= MARGIN


def outside(problem: sb.DesignProblem, x: np.ndarray) -> np.ndarray:
    """``x`` with every anchor 0.1 m out of the arm's plane: clear of the arm, within the bounds, and no rule
    broken (zero-free-length springs have no constraint rows), so only a round's linearised rows can miss it."""
    names = problem.variables.names
    out = np.array(x, dtype=float)
    for index, name in enumerate(names):
        if name.endswith(".y"):
            out[index] = 0.1
    return out


def stopping_outside(monkeypatch: pytest.MonkeyPatch, rounds: int, iterate) -> list[np.ndarray]:
    """Make the first ``rounds`` fitting rounds stop infeasible with ``iterate(problem, start)`` as their least
    violating iterate (a design that meets every rule); returns the iterates they reported."""
    real = clearance_round.solve_problem
    reported: list[np.ndarray] = []

    def solve(problem: sb.DesignProblem, **options):
        if len(reported) >= rounds:
            return real(problem, **options)
        x = iterate(problem, np.array(options["initial"], dtype=float))
        reported.append(x)
        objective = float(problem.objective_value(problem.evaluate(x)))
        violation = max(problem.linear_violation(x), 1.0)  # the round's rows: missed
        record = StartRecord(0, x, x, objective, violation, "ipopt: Infeasible_Problem_Detected", 12, 0.0)
        raise SolverError("no start met the rows", problem, [record])

    monkeypatch.setattr(clearance_round, "solve_problem", solve)
    return reported


def test_meets_rules_tells_a_design_from_a_broken_one(problem):
    """A design within its bounds and rules meets them; the broken one (stiffness -50 N/m < 0) does not."""
    fitted, start = problem
    assert clearance_round.meets_rules(fitted, start)
    assert clearance_round.meets_rules(fitted, outside(fitted, start))
    assert not clearance_round.meets_rules(fitted, broken(fitted, start))


def test_rounds_that_only_miss_their_linearised_rows_do_not_stop_the_fit(problem, monkeypatch):
    """More rounds in a row than INFEASIBLE_ROUNDS stop infeasible, each at its own start: a design of the
    problem (the in-plane optimum, through link2) that misses only the round's cuts. The loop goes on from
    there, as after any round, and the real rounds that follow fit the springs clear (before, it gave up
    after two such rounds and fell back to the start, not converged)."""
    fitted, start = problem
    count = clearance_round.INFEASIBLE_ROUNDS + 1
    reported = stopping_outside(monkeypatch, count, lambda problem, x: x)
    solution, fit, rows = fit_to_arm(fitted, Solution(start, [], "auto", 0, "given"), **OPTIONS)
    assert len(reported) == count
    assert fit.converged and fit.rounds > count
    assert "fell back" not in solution.status
    assert within_bounds(fitted, solution.x)
    assert rows.evaluate(solution.x).max_violation <= 1e-6
    assert rows.linear_violation(solution.x) <= 1e-6
    for row in sb.DesignResult(fitted, solution.x, fit=fit).clearance(samples=256).rows:
        assert row.distance >= MARGIN


def test_a_clear_design_outside_its_rows_is_not_the_fit(problem, monkeypatch):
    """The first round stops infeasible at a clear design that meets every rule but misses the round's rows:
    it is not returned as the fit; the next round starts from it and must meet its own rows."""
    fitted, start = problem
    reported = stopping_outside(monkeypatch, 1, outside)
    solution, fit, rows = fit_to_arm(fitted, Solution(start, [], "auto", 0, "given"), **OPTIONS)
    assert len(reported) == 1
    assert fit.rounds >= 2
    assert rows.linear_violation(solution.x) <= 1e-6
    assert within_bounds(fitted, solution.x)


def _fit(rounds: int, converged: bool, status: str = "ipopt: Solve_Succeeded") -> tuple:
    """A fit as fit_to_arm returns it: its solution (with the status), its record (fitted at 1.5 times the
    objective before, beyond clearance_round.AT_BEST), its problem (unused here)."""
    return Solution(np.zeros(1), [], "ipopt", 0, status), FitRecord(rounds, 4, converged, 1.0, 1.5), None


def test_a_fit_that_had_to_move_its_design_is_compared_with_the_next_design_once():
    # the best start converged only after 4 rounds moved it: the next ranked design is fitted too, once
    assert clearance_round.fall_back([_fit(4, True)], 0)
    assert not clearance_round.fall_back([_fit(4, True), _fit(0, True)], 1)
    # a start clear as it stands (0 rounds) is not compared
    assert not clearance_round.fall_back([_fit(0, True)], 0)


def test_while_no_fit_converged_the_next_designs_are_fitted():
    # whether a round stopped infeasible or the rounds ran out: up to FALLBACK_STARTS more, not one beyond
    stopped = _fit(3, False, f"ipopt: Solve_Succeeded; {clearance_round.INFEASIBLE_NOTE} (x)")
    ran_out = _fit(48, False)
    for fit in (stopped, ran_out):
        assert clearance_round.fall_back([fit], 0)
        assert clearance_round.fall_back([fit, fit], clearance_round.FALLBACK_STARTS - 1)
        assert not clearance_round.fall_back([fit, fit, fit], clearance_round.FALLBACK_STARTS)
    # once one converged (to an accepted design clear as it stood), no more
    assert not clearance_round.fall_back([ran_out, _fit(0, True)], 1)
