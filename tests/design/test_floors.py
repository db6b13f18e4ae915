"""A start whose fatigue floor ends above its coil's least force keeps its design with the floor lowered to it
(springbalance.design.solvers.floors): the floor is an auxiliary bound, the torque does not depend on it."""

from __future__ import annotations

import numpy as np
import pytest

import springbalance as sb
from duty_helpers import duty_coil_problem
from springbalance.design.solvers.floors import lowered_floors
from springbalance.design.solvers.records import FEASIBILITY_TOLERANCE


@pytest.fixture(scope="module")
def solved():
    problem = duty_coil_problem(8)
    return problem, sb.solve(problem, starts=1, verify="off", progress=False)


@pytest.mark.parametrize(
    ("variable", "extreme", "offset"),
    [("forearm.fatigue_min_force", np.min, 3e-5), ("forearm.fatigue_max_force", np.max, -3e-5)],
    ids=["floor-above-the-least-force", "ceiling-below-the-largest-force"],
)
def test_a_bound_past_the_force_is_moved_to_it_and_the_rest_kept(solved, variable, extreme, offset):
    """A floor 30 µN above the coil's least tension at the samples is lowered to it, a ceiling 30 µN below its
    largest raised to it (within IPOPT's scaled tolerance, beyond FEASIBILITY_TOLERANCE); nothing else moves."""
    problem, result = solved
    bound = problem.variables.names.index(variable)
    past = np.array(result.x, dtype=float)
    force = float(extreme(problem.evaluate(past).tensions[:, 0]))  # the coil's least or largest tension [N]
    past[bound] = force + offset
    evaluation = problem.evaluate(past)
    assert evaluation.max_violation == pytest.approx(3e-5, rel=1e-6)
    moved = lowered_floors(problem, evaluation)
    assert moved is not None
    assert moved[bound] == pytest.approx(force, abs=1e-12)
    others = np.arange(past.size) != bound
    assert np.array_equal(moved[others], past[others])
    after = problem.evaluate(moved)
    assert after.max_violation <= FEASIBILITY_TOLERANCE
    np.testing.assert_array_equal(after.tau, evaluation.tau)  # the torque does not see the bounds


def test_a_floor_at_or_below_the_least_force_is_left_alone(solved):
    problem, result = solved
    evaluation = problem.evaluate(np.array(result.x, dtype=float))
    assert lowered_floors(problem, evaluation) is None
