"""The rule of ``worse_joint`` (:mod:`springbalance.design.worse_joints`): which joints a design carries worse
than the bare arm."""

from __future__ import annotations

import numpy as np

import springbalance as sb
from springbalance.design.solvers.records import FEASIBILITY_TOLERANCE
from springbalance.design.worse_joints import TORQUE_TOLERANCE, weighted_joints_made_worse, worse_rows


def _row(joint: str, peak: tuple[float, float], rms: tuple[float, float]) -> dict:
    return {"joint": joint, "peak_before": peak[0], "peak_after": peak[1], "rms_before": rms[0], "rms_after": rms[1]}


def test_a_joint_is_worse_when_its_peak_or_its_rms_grows_beyond_round_off():
    rows = [
        _row("shoulder", (10.0, 2.0), (6.0, 1.0)),  # better on both
        _row("elbow", (4.0, 4.5), (2.0, 1.5)),  # peak worse, RMS better
        _row("wrist", (1.0, 0.9), (0.5, 0.6)),  # RMS worse
        _row("roll", (1.0, 1.0 + 0.5 * TORQUE_TOLERANCE * 10.0), (0.5, 0.5)),  # within round-off of the largest peak
    ]
    found = worse_rows(rows)
    assert [row["joint"] for row in found] == ["elbow", "wrist"]
    assert found[0]["worse"] == ["peak"] and found[1]["worse"] == ["RMS"]


def test_a_peak_within_the_solvers_feasibility_tolerance_of_the_bare_arms_is_not_worse():
    """A design held within the bare arm's peaks meets those rows within the solver's tolerance [N·m]: a peak that
    much above the bare arm's is no worse, even where that is more than the round-off of the largest peak."""
    largest = 3.9  # N·m: TORQUE_TOLERANCE × 3.9 is far below the solver's tolerance
    assert TORQUE_TOLERANCE * largest < 0.1 * FEASIBILITY_TOLERANCE
    within = _row("elbow", (largest, largest + 0.5 * FEASIBILITY_TOLERANCE), (3.0, 1.9))
    beyond = _row("elbow", (largest, largest + 2.0 * FEASIBILITY_TOLERANCE), (3.0, 1.9))
    assert worse_rows([within]) == []
    assert [row["worse"] for row in worse_rows([beyond])] == [["peak"]]


def test_without_gravity_the_springs_own_largest_peak_sets_the_round_off():
    rows = [_row("a", (0.0, 3.0), (0.0, 1.0)), _row("b", (0.0, 0.0), (0.0, 1e-12))]
    assert [row["joint"] for row in worse_rows(rows)] == ["a"]


def test_a_joint_of_weight_zero_is_not_a_weighted_joint_made_worse():
    """The two-link arm with a spring from the ground to link 2 that pulls the elbow hard: the elbow is carried worse;
    with the elbow's weight 0 it is not counted."""
    arm = sb.Mechanism.from_urdf("urdf/two_link_planar.urdf")
    workspace = sb.Workspace.sobol(arm, n=64, seed=0)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0.0, 0.0, 0.5]), sb.Anchor("link2", [0.3, 0.0, 0.0]), name="s", stiffness=5000.0
    )
    every = sb.DesignResult(sb.DesignProblem(arm, workspace, [spring]), np.zeros(0)).joints_made_worse()
    worse = {row["joint"] for row in every}
    assert "elbow" in worse  # the premise
    for weights in (None, {"elbow": 0.0}):
        problem = sb.DesignProblem(arm, workspace, [spring], weights=weights)
        expected = worse if weights is None else worse - {"elbow"}
        assert set(weighted_joints_made_worse(problem, np.zeros(problem.variables.size))) == expected
