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


def test_a_floor_above_the_least_force_is_lowered_to_it_and_the_rest_kept(solved):
    problem, result = solved
    floor = problem.variables.names.index("forearm.fatigue_min_force")
    above = np.array(result.x, dtype=float)
    least = float(np.min(problem.evaluate(above).tensions[:, 0]))  # the coil's tension at the samples [N]
    above[floor] = least + 3e-5  # 30 µN above: within IPOPT's scaled tolerance, beyond FEASIBILITY_TOLERANCE
    evaluation = problem.evaluate(above)
    assert evaluation.max_violation == pytest.approx(3e-5, rel=1e-6)
    lowered = lowered_floors(problem, evaluation)
    assert lowered is not None
    assert lowered[floor] == pytest.approx(least, abs=1e-12)
    others = np.arange(above.size) != floor
    assert np.array_equal(lowered[others], above[others])
    after = problem.evaluate(lowered)
    assert after.max_violation <= FEASIBILITY_TOLERANCE
    np.testing.assert_array_equal(after.tau, evaluation.tau)  # the torque does not see the floor


def test_a_floor_at_or_below_the_least_force_is_left_alone(solved):
    problem, result = solved
    evaluation = problem.evaluate(np.array(result.x, dtype=float))
    assert lowered_floors(problem, evaluation) is None


def test_a_ceiling_below_the_largest_force_is_raised_to_it_and_the_rest_kept(solved):
    problem, result = solved
    ceiling = problem.variables.names.index("forearm.fatigue_max_force")
    below = np.array(result.x, dtype=float)
    largest = float(np.max(problem.evaluate(below).tensions[:, 0]))  # the coil's largest tension at the samples [N]
    below[ceiling] = largest - 3e-5  # 30 µN below
    evaluation = problem.evaluate(below)
    assert evaluation.max_violation == pytest.approx(3e-5, rel=1e-6)
    raised = lowered_floors(problem, evaluation)
    assert raised is not None
    assert raised[ceiling] == pytest.approx(largest, abs=1e-12)
    others = np.arange(below.size) != ceiling
    assert np.array_equal(raised[others], below[others])
    assert problem.evaluate(raised).max_violation <= FEASIBILITY_TOLERANCE
