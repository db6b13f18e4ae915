"""The clearance loop's trust region (springbalance.design.clearance_round.trust_rows): the rows, the rounds that
solve inside it, and the second run of the loop that uses it when the first one did not converge.

The arm and springs are those of tests/design/test_clearance_fit_infeasible.py: the two-link planar arm with
collision boxes, a ground→link1 and a link1→link2 zero-free-length spring whose anchors may leave the arm's plane
by 0.1 m, fitted from the in-plane optimum, whose first spring passes through link2.
"""

from __future__ import annotations

import numpy as np
import pytest

import springbalance as sb
from clearance_helpers import crossing_case
from springbalance.design import clearance_fit, clearance_round
from springbalance.design.clearance_fit import fit_to_arm
from springbalance.design.clearance_round import TRUST_LENGTH, TRUST_REGION, trust_rows
from springbalance.design.solvers import Solution

OPTIONS = {"method": "auto", "max_iterations": 100, "tolerance": 1e-8, "polish_iterations": None}
MARGIN = 0.005


@pytest.fixture(scope="module")
def problem():
    return crossing_case(MARGIN)


def _spans(problem: sb.DesignProblem) -> np.ndarray:
    lower, upper = (np.asarray(bound, dtype=float) for bound in problem.variables.bounds())
    return upper - lower


def test_the_rows_hold_each_variable_within_a_tenth_of_its_range(problem):
    """Each free variable gets two rows; a step of 10 % of its range lies on its row (value 0), 11 % breaks it by
    TRUST_LENGTH × 1 % [m], and a step of another variable leaves it untouched."""
    fitted, start = problem
    span = _spans(fitted)
    free = np.flatnonzero(np.isfinite(span) & (span > 0))
    rows = trust_rows(fitted, start)
    assert rows is not None and len(rows) == 2 * free.size
    matrix, offset = fitted.with_linear_rows(rows).linear_matrix()
    values = matrix @ start + offset
    np.testing.assert_allclose(values, TRUST_LENGTH * TRUST_REGION, rtol=1e-12)
    i = int(free[0])
    for fraction, expected in ((TRUST_REGION, 0.0), (TRUST_REGION + 0.01, -0.01 * TRUST_LENGTH)):
        for sign in (1.0, -1.0):
            moved = np.array(start, dtype=float)
            moved[i] += sign * fraction * span[i]
            assert np.min(matrix @ moved + offset) == pytest.approx(expected, abs=1e-12)
    assert all("within its trust region" in label for label in rows.labels)


def test_a_trusted_round_moves_no_variable_beyond_its_trust_region(problem, monkeypatch):
    """With ``trusted``, every round that met its rows inside the trust region moved each variable by at most that
    fraction of its range; the fit still clears the arm (measured on the URDF's own shapes). The region is widened
    to half of each range here: the anchors must leave the arm's plane by 0.1 m of their 0.2 m, more than 10 % can
    reach in the rounds the fit takes (such rounds are solved again without it, as in the first run)."""
    fitted, start = problem
    region = 0.5
    monkeypatch.setattr(clearance_round, "TRUST_REGION", region)
    span = _spans(fitted)
    real = clearance_round._solved_round
    steps = []

    def recorded(round_problem, x, solution, options):
        resolved, note = real(round_problem, x, solution, options)
        labels = round_problem.linear_rows.labels if round_problem.linear_rows is not None else []
        if resolved is not None and not note and any("trust region" in label for label in labels):
            steps.append(np.abs(np.asarray(resolved.x) - np.asarray(x)))
        return resolved, note

    monkeypatch.setattr(clearance_round, "_solved_round", recorded)
    solution, fit, rows = clearance_fit._fitted(fitted, Solution(start, [], "auto", 0, "given"), None, True, OPTIONS)
    assert steps, "no round met its rows inside its trust region"
    finite = np.isfinite(span)
    for step in steps:
        assert np.all(step[finite] <= region * span[finite] * (1 + 1e-6) + 1e-9)
    assert fit.converged
    for row in sb.DesignResult(rows, solution.x, fit=fit).clearance(samples=256).rows:
        assert row.distance >= MARGIN


def test_a_fit_that_did_not_converge_runs_again_with_the_trust_region(problem, monkeypatch):
    """The loop's first run is made to end unconverged; the second one, with the trust region, converges and is the
    fit kept, its record counting the rounds of both. When the first run converges, it alone runs."""
    fitted, start = problem
    real = clearance_fit._fitted
    runs = []

    def first_fails(*arguments):
        trusted = arguments[3]
        runs.append(trusted)
        solution, record, rows = real(*arguments)
        if not trusted:
            record.converged = False
        return solution, record, rows

    monkeypatch.setattr(clearance_fit, "_fitted", first_fails)
    solution, fit, rows = fit_to_arm(fitted, Solution(start, [], "auto", 0, "given"), **OPTIONS)
    assert runs == [False, True]
    assert fit.converged and fit.rounds >= 2  # each run needed at least one round from the crossing start
    for row in sb.DesignResult(rows, solution.x, fit=fit).clearance(samples=256).rows:
        assert row.distance >= MARGIN
    runs.clear()
    monkeypatch.setattr(clearance_fit, "_fitted", lambda *arguments: (runs.append(arguments[3]), real(*arguments))[1])
    assert fit_to_arm(fitted, Solution(start, [], "auto", 0, "given"), **OPTIONS)[1].converged
    assert runs == [False]
