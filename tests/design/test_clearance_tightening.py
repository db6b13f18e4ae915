"""The rounds that tighten a fitted design (springbalance.design.clearance_round.Tightening): after the loop's first
fitted design, rounds with the rows linearised again there go on while they lower the objective, and the fitted
design of lowest objective is the fit's.

The arm and springs are tests/clearance_helpers.py's crossing case (the two-link planar arm with collision boxes,
two zero-free-length springs whose anchors may leave the arm's plane by 0.1 m, fitted from the in-plane optimum,
whose first spring passes through link2). The rounds' designs are scripted where a test needs a given sequence of
objectives; the checks of the first design are the real ones.
"""

from __future__ import annotations

import numpy as np
import pytest

import springbalance as sb
from clearance_helpers import crossing_case
from springbalance.design import clearance_fit, clearance_round
from springbalance.design.clearance_round import INFEASIBLE_NOTE, TIGHTEN_GAIN, TIGHTEN_ROUNDS, Tightening
from springbalance.design.solvers import Solution

OPTIONS = {"method": "auto", "max_iterations": 100, "tolerance": 1e-8, "polish_iterations": None}
MARGIN = 0.005
#: the loop's own check (a test may script it more than once)
REAL_VIOLATIONS = clearance_fit._violations


@pytest.fixture(scope="module")
def case():
    problem, start = crossing_case(MARGIN)
    fitted = clearance_fit.fit_to_arm(problem, Solution(start, [], "auto", 0, "given"), tighten=True, **OPTIONS)[0]
    return problem, start, np.asarray(fitted.x, dtype=float)


def _objective(problem: sb.DesignProblem, x: np.ndarray) -> float:
    return float(problem.objective_value(problem.evaluate(x)))


def scaled(problem: sb.DesignProblem, fitted: np.ndarray, factor: float) -> np.ndarray:
    """``fitted`` with its springs' stiffnesses multiplied by ``factor``."""
    stiff = [i for i, name in enumerate(problem.variables.names) if name.endswith(".stiffness")]
    assert stiff
    x = np.array(fitted, dtype=float)
    x[stiff] *= factor
    return x


def _designs(problem: sb.DesignProblem, fitted: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Three designs of objectives ``middle > low < high``, ``middle`` above ``low`` by more than the gain: the
    fitted design with its stiffnesses scaled."""
    low, middle, high = (scaled(problem, fitted, f) for f in (1.0, 0.8, 0.7))
    assert _objective(problem, middle) > _objective(problem, low) * (1 + 10 * TIGHTEN_GAIN)
    assert _objective(problem, high) > _objective(problem, low)
    return low, middle, high


def _scripted(monkeypatch, designs: list[tuple[np.ndarray | None, str]]) -> list[np.ndarray]:
    """Each round returns the next of ``designs`` (a design and its note; None: the solver returned nothing);
    every design after the start is clear of the arm. Returns the list of the rounds' starting designs."""
    starts: list[np.ndarray] = []
    queue = list(designs)

    def solve_round(problem, x, solution, options, trusted=False):
        starts.append(np.array(x, dtype=float))
        design, note = queue.pop(0)
        if design is None:
            return None, ""
        return Solution(design, solution.starts, solution.method, solution.seed, f"round {len(starts)}"), note

    def violations(checker, x):
        if not starts:  # the start: the real check (its first spring passes through link2)
            return REAL_VIOLATIONS(checker, x)
        return {}, {name: 1.0 for name in checker.by_name}

    monkeypatch.setattr(clearance_fit, "solve_round", solve_round)
    monkeypatch.setattr(clearance_fit, "_violations", violations)
    return starts


def test_a_fitted_design_is_tightened_to_the_real_clearance_and_stays_clear(case):
    """Unscripted: the fit with its tightening rounds ends clear of the arm on the URDF's own shapes at 4× the
    check's poses, no worse than the fit without them."""
    problem, start, _ = case
    solution, fit, rows = clearance_fit.fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), tighten=True, **OPTIONS
    )
    untightened = clearance_fit.fit_to_arm(problem, Solution(start, [], "auto", 0, "given"), **OPTIONS)
    assert fit.converged and untightened[1].converged
    assert fit.rounds > untightened[1].rounds  # a round at least, linearised at the fitted design
    assert fit.objective <= untightened[1].objective * (1 + 1e-9)
    for row in sb.DesignResult(rows, solution.x, fit=fit).clearance(samples=256).rows:
        assert row.distance >= MARGIN


def test_the_rounds_go_on_while_the_objective_falls_and_keep_the_lowest(case, monkeypatch):
    """Scripted rounds: the first fitted design (middle), a lower one (low), a higher one (high). The loop tightens
    from middle and from low, stops after high (it did not lower the objective) and returns low, converged, with
    the rows of its own round; each tightening round starts from the design before it."""
    problem, start, fitted = case
    low, middle, high = _designs(problem, fitted)
    starts = _scripted(monkeypatch, [(middle, ""), (low, ""), (high, "")])
    solution, fit, rows = clearance_fit.fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), tighten=True, **OPTIONS
    )
    assert len(starts) == 3
    np.testing.assert_array_equal(starts[1], middle)
    np.testing.assert_array_equal(starts[2], low)
    np.testing.assert_array_equal(solution.x, low)
    assert solution.status.startswith("round 2")
    assert fit.converged and fit.rounds == 3
    assert fit.objective == pytest.approx(_objective(problem, low), rel=1e-12)


def test_tightening_stops_after_its_rounds(case, monkeypatch):
    """Rounds that keep lowering the objective stop after TIGHTEN_ROUNDS of them; the last is kept."""
    problem, start, fitted = case
    factors = np.linspace(0.5, 0.95, TIGHTEN_ROUNDS + 3)
    designs = [scaled(problem, fitted, factor) for factor in factors]
    values = [_objective(problem, x) for x in designs]
    assert all(b < a * (1 - TIGHTEN_GAIN) for a, b in zip(values, values[1:]))  # each one lower
    starts = _scripted(monkeypatch, [(x, "") for x in designs])
    solution, fit, _ = clearance_fit.fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), tighten=True, **OPTIONS
    )
    assert len(starts) == 1 + TIGHTEN_ROUNDS
    np.testing.assert_array_equal(solution.x, designs[TIGHTEN_ROUNDS])
    assert fit.converged


def test_a_tightening_round_that_breaks_its_rows_falls_back_to_the_best_fitted_design(case, monkeypatch):
    """After the first fitted design, the rounds stop infeasible: the loop gives up after INFEASIBLE_ROUNDS of them
    and returns the fitted design, converged (not the design of a round that broke its rows, as without a fitted
    design before it); so does a round for which the solver returned nothing."""
    problem, start, fitted = case
    low, middle, _ = _designs(problem, fitted)
    _scripted(monkeypatch, [(middle, ""), (low, f"{INFEASIBLE_NOTE} (x)"), (low, f"{INFEASIBLE_NOTE} (x)")])
    solution, fit, _ = clearance_fit.fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), tighten=True, **OPTIONS
    )
    np.testing.assert_array_equal(solution.x, middle)
    assert fit.converged and "NOT converged" not in solution.status
    _scripted(monkeypatch, [(middle, ""), (None, "")])
    solution, fit, _ = clearance_fit.fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), tighten=True, **OPTIONS
    )
    np.testing.assert_array_equal(solution.x, middle)
    assert fit.converged


@pytest.mark.parametrize("trusted_first", [False, True])
def test_a_fit_not_asked_to_tighten_ends_at_its_first_fitted_design(case, monkeypatch, trusted_first):
    """Without ``tighten`` (the ideal twin of coils, a problem with free coils): the first fitted design ends the
    loop, with or without the trust region first."""
    problem, start, fitted = case
    low, middle, _ = _designs(problem, fitted)
    starts = _scripted(monkeypatch, [(middle, ""), (low, "")])
    solution, fit, _ = clearance_fit.fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), trusted_first=trusted_first, **OPTIONS
    )
    assert len(starts) == 1
    np.testing.assert_array_equal(solution.x, middle)
    assert fit.converged and fit.rounds == 1


def test_a_design_clear_as_it_stands_is_not_tightened(case, monkeypatch):
    """The multi-start's optimum clear as it stands (no round ran) is the fit: it is the optimum without rows."""
    problem, start, fitted = case
    calls = []
    monkeypatch.setattr(clearance_fit, "solve_round", lambda *arguments: calls.append(1))
    solution, fit, _ = clearance_fit.fit_to_arm(
        problem, Solution(fitted, [], "auto", 0, "given"), tighten=True, **OPTIONS
    )
    assert not calls and fit.rounds == 0 and fit.converged
    np.testing.assert_array_equal(solution.x, fitted)


def test_the_record_keeps_the_lowest_objective_and_counts_its_rounds():
    """Tightening alone: a rise ends it, a fall by less than the gain ends it, the lowest is kept."""
    tightening = Tightening()
    assert tightening.goes_on(10.0, ("a",), rounds=1, limit=24)
    assert tightening.goes_on(9.0, ("b",), rounds=2, limit=24)
    assert not tightening.goes_on(9.5, ("c",), rounds=3, limit=24)
    assert tightening.best == ("b",) and tightening.objective == 9.0
    small = Tightening()
    assert small.goes_on(10.0, ("a",), 1, 24)
    assert not small.goes_on(10.0 * (1 - TIGHTEN_GAIN / 2), ("b",), 2, 24)  # lower, but by less than the gain
    assert small.best == ("b",)
    assert not Tightening().goes_on(1.0, ("a",), rounds=24, limit=24)  # no round left
    assert clearance_round.TIGHTEN_ROUNDS == TIGHTEN_ROUNDS
