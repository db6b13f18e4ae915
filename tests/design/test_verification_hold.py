"""A design whose joints the pipeline held within the bare arm's peaks stays held through the verification's
re-solves (springbalance.design.verification_loop, ``held``)."""

from __future__ import annotations

import pytest

import springbalance as sb
from springbalance.design.solvers import Solution
from springbalance.design.verification_loop import verify_and_resolve
from springbalance.design.worse_joints import weighted_joints_made_worse
from two_link_helpers import crossing_spring

URDF = "urdf/two_link_planar.urdf"


def _crossing(n: int, max_length: float) -> sb.DesignProblem:
    """One spring from the ground to link 2, across both joints, shoulder at weight 1 and elbow at 0.01: the least
    RMS balances the shoulder and loads the elbow beyond the bare arm's peak, so the pipeline holds the elbow. On
    ``n`` Sobol samples its ``max_length`` binds at the samples and fails between them, so the verification at
    unseen poses re-solves."""
    mechanism = sb.Mechanism.from_urdf(URDF)
    ranges = {"shoulder": [-90, 90], "elbow": [-90, 90]}
    workspace = sb.Workspace.sobol(mechanism, n=n, seed=0, ranges=ranges, degrees=True)
    springs = [crossing_spring(max_length=max_length)]
    return sb.DesignProblem(mechanism, workspace, springs, weights={"shoulder": 1.0, "elbow": 0.01})


@pytest.mark.parametrize(("n", "max_length"), [(24, 0.6), (24, 0.7), (32, 0.6), (32, 0.7)])
def test_the_verifications_re_solves_keep_the_held_joints_held(n, max_length):
    result = sb.solve(_crossing(n, max_length), starts=2, progress=False)
    assert result.joint_hold is not None and result.joint_hold.held and result.joint_hold.joints == ["elbow"]
    assert result.verification is not None and result.verification.rounds >= 1 and result.verification.passed
    assert weighted_joints_made_worse(result.problem, result.x) == []
    assert result.ok, result.failures()


def test_without_the_hold_the_re_solves_load_the_elbow_again():
    """The same held design verified as if nothing had held it: the re-solves meet the length rule at the new poses
    and, free to, load the elbow far beyond the bare arm's peak again."""
    problem = _crossing(24, 0.6)
    result = sb.solve(problem, starts=2, progress=False, verify="off")
    assert result.joint_hold is not None and result.joint_hold.held
    solution = Solution(result.x, [], "auto", 0, "held")
    unheld, record, _ = verify_and_resolve(problem, solution, "resolve", held=False)
    assert record.rounds >= 1
    assert weighted_joints_made_worse(problem, unheld.x) == ["elbow"]
    held, record, _ = verify_and_resolve(problem, solution, "resolve", held=True)
    assert record.rounds >= 1 and record.passed
    assert weighted_joints_made_worse(problem, held.x) == []
