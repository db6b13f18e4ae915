"""``arm_through_floor``: a workspace that takes the arm's own links through its floor is reported.

The two-link arm of urdf/two_link_planar_collision.urdf (shoulder at the world origin; link1 a 0.5 m box of
0.04 m section, link2 a 0.4 m box of 0.03 m, the tool a sphere of 0.03 m at link2's tip) over shoulder and elbow
in ±80°: its lowest point, from the boxes' corners and the sphere placed by Pinocchio (not by coal), reaches
0.88 m below the shoulder. A floor 0.6 m below it is passed through at some poses; one 1 m below, at none.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from springbalance.model.collision import CollisionScene
from springbalance.model.floor import FLOOR
from springbalance.results.floor_flags import FLOOR_TOLERANCE, arm_through_floor_flags

URDF = Path(__file__).resolve().parents[2] / "urdf" / "two_link_planar_collision.urdf"
RANGES = {"shoulder": [-80, 80], "elbow": [-80, 80]}
#: per link frame, the collision box's centre and half sides [m] (the URDF's), and the tool's sphere radius [m]
BOXES = {"link1": ((0.25, 0, 0), (0.25, 0.02, 0.02)), "link2": ((0.2, 0, 0), (0.2, 0.015, 0.015))}
TOOL_RADIUS = 0.03


def _design(floor: float | None) -> sb.DesignResult:
    arm = sb.Mechanism.from_urdf(URDF, floor=floor)
    workspace = sb.Workspace.sobol(arm, n=128, ranges=RANGES, degrees=True, seed=3)
    spring = sb.ZeroFreeLengthSpring(sb.Anchor("universe", (0, 0, 0.3)), sb.Anchor("link1", (0.3, 0, 0)), stiffness=50)
    problem = sb.DesignProblem(arm, workspace, [spring])
    return sb.DesignResult(problem, np.asarray(problem.variables.start, dtype=float))


def _lowest(design: sb.DesignResult) -> np.ndarray:
    """Per pose, the lowest world z [m] of the arm's collision shapes, from their corners and the tool's sphere."""
    arm = design.problem.mechanism
    data = arm.model.createData()
    lowest = []
    for q in arm.configurations(design.problem.base_workspace.joint_values):
        pin.framesForwardKinematics(arm.model, data, q)
        heights = []
        for body, (centre, half) in BOXES.items():
            frame = data.oMf[arm.frame_id(body)]
            for signs in itertools.product((-1, 1), repeat=3):
                heights.append(frame.act(np.array(centre) + np.array(signs) * np.array(half))[2])
        heights.append(data.oMf[arm.frame_id("tool")].translation[2] - TOOL_RADIUS)
        lowest.append(min(heights))
    return np.array(lowest)


def test_a_floor_the_arm_reaches_through_is_reported_with_its_poses_and_depth():
    design = _design(-0.6)
    lowest = _lowest(design)
    expected = int(np.sum(lowest < -0.6 - FLOOR_TOLERANCE))
    assert 0 < expected < lowest.size  # some poses, not all
    (flag,) = arm_through_floor_flags(design)
    assert flag.kind == "arm_through_floor" and flag.severity == "warning"
    count = re.search(r"at (\d+) of (\d+) workspace poses, (\S+) deepest by ([\d.]+) mm", flag.message)
    assert count is not None, flag.message
    assert (int(count[1]), int(count[2])) == (expected, lowest.size)
    assert count[3] in ("link2", "tool")
    assert float(count[4]) == pytest.approx(1e3 * (-0.6 - lowest.min()), abs=0.1)
    assert "arm_through_floor" in {finding.kind for finding in design.warnings()}  # (the report's Warnings)


@pytest.mark.parametrize("floor", [-1.0, None])
def test_a_floor_below_the_arm_or_none_is_not_reported(floor):
    design = _design(floor)
    assert _lowest(design).min() > -0.95
    assert arm_through_floor_flags(design) == []


def test_an_arm_without_a_urdf_has_the_floor_alone_and_no_warning():
    """A mechanism built from a Pinocchio model has no links' geometry: its collision geometry is the floor alone
    (the springs can still be kept above it), and the warning has no link to measure (it raised before)."""
    arm = sb.Mechanism(sb.Mechanism.from_urdf(URDF).model, floor=0.0)
    assert CollisionScene(arm).links == [FLOOR]
    workspace = sb.Workspace.sobol(arm, n=8, seed=0)
    spring = sb.ZeroFreeLengthSpring(sb.Anchor("link1", (0.3, 0, 0)), sb.Anchor("link2", (0.2, 0, 0)), stiffness=50)
    problem = sb.DesignProblem(arm, workspace, [spring])
    design = sb.DesignResult(problem, np.asarray(problem.variables.start, dtype=float))
    assert arm_through_floor_flags(design) == [] and "arm_through_floor" not in {w.kind for w in design.warnings()}
