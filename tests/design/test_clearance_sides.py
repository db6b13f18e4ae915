"""The side of each link a clear design passes on, as rows (springbalance.design.clearance_sides.side_rows).

The arm and springs are those of tests/design/test_clearance_constraint.py: the two-link planar arm with collision
boxes, a ground→link1 spring s1 whose in-plane optimum crosses the folded-back link2, and a link1→link2 spring s2;
every anchor may leave the arm's plane by 0.1 m. The fit moves s1 out of the plane, to one side of link2. The arm
is symmetric about its plane, so the design mirrored through it (every anchor's y negated) has the same objective
and is as clear, but passes link2 on the other side: the rows tell the two apart.
"""

from __future__ import annotations

import numpy as np
import pytest

import springbalance as sb
from clearance_helpers import crossing_case, crossing_springs
from springbalance.design.clearance_fit import fit_to_arm
from springbalance.design.clearance_sides import side_rows
from springbalance.design.solvers import Solution

MARGIN = 0.005


@pytest.fixture(scope="module")
def fitted():
    """The problem and its design fitted 5 mm clear of the arm from the in-plane optimum."""
    problem, start = crossing_case(MARGIN)
    solution, fit, _ = fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), method="auto", max_iterations=100, tolerance=1e-8
    )
    assert fit.converged
    return problem, np.asarray(solution.x, dtype=float)


def _mirrored(problem: sb.DesignProblem, x: np.ndarray) -> np.ndarray:
    """``x`` with every anchor mirrored through the arm's plane (y → −y)."""
    return np.array([-value if name.endswith(".y") else value for name, value in zip(problem.variables.names, x)])


def test_the_rows_hold_at_the_design_and_name_the_side(fitted):
    problem, x = fitted
    rows = side_rows(problem, x)
    assert rows is not None and len(rows) >= 2
    matrix, offset = problem.with_linear_rows(rows).linear_matrix()
    assert np.min(matrix @ x + offset) >= 0
    assert all(label.endswith("the side it passes on") for label in rows.labels)
    assert any(label.startswith("s1 clear of link2") for label in rows.labels)


def test_the_mirrored_design_is_as_good_and_as_clear_but_breaks_the_rows(fitted):
    """The mirror image passes link2 on the other side: same objective, clear by the margin at 640 poses of the
    URDF's own shapes, yet s1's rows at link2 are broken by millimetres."""
    problem, x = fitted
    mirrored = _mirrored(problem, x)
    objective = problem.objective_value(problem.evaluate(x))
    assert problem.objective_value(problem.evaluate(mirrored)) == pytest.approx(objective, rel=1e-9)
    assert min(row.distance for row in sb.DesignResult(problem, mirrored).clearance(samples=640).rows) >= MARGIN
    rows = side_rows(problem, x)
    matrix, offset = problem.with_linear_rows(rows).linear_matrix()
    values = matrix @ mirrored + offset
    broken = [label for label, value in zip(rows.labels, values) if value < -0.001]
    assert any(label.startswith("s1 clear of link2") for label in broken), broken


def test_no_clearance_no_rows(fitted):
    problem, x = fitted
    bare = sb.DesignProblem(problem.mechanism, problem.workspace, crossing_springs(0.1))
    assert side_rows(bare, x) is None
