"""A design that carries a weighted joint worse than the bare arm, solved again with the joints held
(springbalance.design.joint_hold, the pipeline's hold_joints step)."""

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.joint_hold import JointHold, held_within_bare_arm
from springbalance.design.solvers import solve_problem
from springbalance.design.worse_joints import TORQUE_TOLERANCE, weighted_joints_made_worse
from two_link_helpers import crossing_spring

URDF = "urdf/two_link_planar.urdf"


@pytest.fixture(scope="module")
def crossing():
    """One spring from the ground to link2, across both joints, elbow ±90°: the least RMS with the shoulder at
    weight 1 and the elbow at 0.01 balances the shoulder and loads the elbow beyond the bare arm's peak (3.924
    N·m); the multi-start's design, before the pipeline holds the joints."""
    mechanism = sb.Mechanism.from_urdf(URDF)
    workspace = sb.Workspace.grid(mechanism, n=9, ranges={"shoulder": [-90, 90], "elbow": [-90, 90]}, degrees=True)
    problem = sb.DesignProblem(mechanism, workspace, [crossing_spring()], weights={"shoulder": 1.0, "elbow": 0.01})
    solution = solve_problem(problem, starts=2, progress=False)
    return problem, solution


def _peaks(problem, x):
    return np.max(np.abs(problem.evaluate(x).tau), axis=0)


def _bare_peaks(problem):
    return np.max(np.abs(problem.workspace.kinematics().gravity_torque), axis=0)


def test_a_design_that_makes_the_elbow_worse_is_held_within_the_bare_arms_peak(crossing):
    problem, solution = crossing
    bare = _bare_peaks(problem)
    assert weighted_joints_made_worse(problem, solution.x) == ["elbow"]
    assert _peaks(problem, solution.x)[1] > 1.1 * bare[1]
    held, record = held_within_bare_arm(problem, solution)
    assert isinstance(record, JointHold) and record.held and record.joints == ["elbow"]
    assert weighted_joints_made_worse(problem, held.x) == []
    peaks = _peaks(problem, held.x)
    assert peaks[1] <= bare[1] + TORQUE_TOLERANCE * bare.max()
    assert peaks[0] < 0.5 * bare[0]  # the shoulder is still balanced in part
    # the record's objectives are the problem's (without the rows that held the joints), before and after
    assert record.objective_before == pytest.approx(problem.objective_value(problem.evaluate(solution.x)), rel=1e-12)
    assert record.objective == pytest.approx(problem.objective_value(problem.evaluate(held.x)), rel=1e-12)
    assert record.objective > record.objective_before  # holding the elbow costs the shoulder
    assert "elbow held within the bare arm's peak" in held.status
    assert held.status.startswith(solution.status) and held.status.endswith("Solve_Succeeded")


def test_a_design_that_makes_no_joint_worse_is_left_as_it_is(crossing):
    problem, solution = crossing
    held, _ = held_within_bare_arm(problem, solution)
    again, record = held_within_bare_arm(problem, held)
    assert again is held and record is None
    # a problem that holds its joints already is not solved again
    holding = problem.with_springs(problem.springs, no_joint_worse=True)
    assert held_within_bare_arm(holding, solution) == (solution, None)


def test_when_no_design_near_it_holds_the_joints_the_design_stays(crossing):
    problem, solution = crossing
    # every variable held: the held solve has nothing to move, and the design breaks the elbow's rows
    kept, record = held_within_bare_arm(problem, solution, fixed=problem.variables.names)
    assert kept is solution
    assert record is not None and not record.held and record.joints == ["elbow"]
    assert record.objective == record.objective_before


def test_the_pipeline_holds_the_joints_and_keeps_the_users_problem(crossing, tmp_path):
    problem, _ = crossing
    result = sb.solve(problem, starts=2)
    assert result.joint_hold is not None and result.joint_hold.held
    assert result.ok and not [flag for flag in result.failures() if flag.kind == "worse_joint"]
    # the design belongs to the problem as given: its objective is the user's, without the rows
    assert not result.problem.no_joint_worse
    assert result.joint_hold.objective == pytest.approx(result.metrics()["objectives"]["rms"]["after"], rel=1e-12)
    # saved and loaded, and in the text report
    loaded = sb.DesignResult.load(result.save(tmp_path / "design.json"))
    assert loaded.joint_hold == result.joint_hold
    assert "elbow held within the bare arm's peak(s)" in loaded.table()
