"""Designs for the scene, plot and report tests: built without solving, so they are fast.

``two_link_design()`` is the two-link planar arm of urdf/two_link_planar.urdf (link1 blue,
RGBA 0.2 0.3 0.8) with two extension springs whose values are the middles of their
bounds (the design vector is the problem's first guess):

- ``shoulder``: ground point (0, 0, 0.15) to a point free on a segment of link1, stiff, so
  its tension is high (dark red on the colour scale);
- ``forearm``: a point free in a box of link1 to a point of link2, soft, so its tension
  stays low (yellow).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import springbalance as sb

ROOT = Path(__file__).resolve().parents[1]
URDF = ROOT / "urdf"
LINK1_RGB = (0.2, 0.3, 0.8)


def two_link_design(n: int = 7) -> sb.DesignResult:
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.grid(mechanism, n, ranges={"shoulder": [-80, 80], "elbow": [-100, 100]}, degrees=True)
    springs = [
        sb.ExtensionSpring(sb.Anchor("universe", (0.0, 0.0, 0.15)),
                           sb.Anchor("link1", sb.Segment((0.1, 0, 0), (0.45, 0, 0), lower=0.4, upper=0.8)),
                           name="shoulder", stiffness=sb.Free(600, 800), free_length=0.05),
        sb.ExtensionSpring(sb.Anchor("link1", sb.Free([0.05, 0, 0.03], [0.2, 0, 0.08])),
                           sb.Anchor("link2", (0.25, 0, 0)),
                           name="forearm", stiffness=20.0, free_length=0.05, keep_tension=False),
    ]
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="rms")
    return sb.DesignResult(problem, np.array(problem.variables.start))


def ur5_design(n: int = 16) -> sb.DesignResult:
    """UR5 (example-robot-data meshes) with two springs anchored off-axis, random samples."""
    mechanism = sb.Mechanism.from_robot("ur5")
    workspace = sb.Workspace.random(mechanism, n, seed=3)
    springs = [
        sb.ExtensionSpring(sb.Anchor("universe", (0.05, 0.1, 0.4)), sb.Anchor("upper_arm_link", (0.02, 0.05, 0.2)),
                           name="s1", stiffness=1500.0, free_length=0.05, keep_tension=False),
        sb.ZeroFreeLengthSpring(sb.Anchor("shoulder_link", sb.Free([-0.1, -0.1, 0.0], [0.1, 0.1, 0.1])),
                                sb.Anchor("forearm_link", (0.1, 0.0, 0.02)), name="s2", stiffness=800.0),
    ]
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="rms")
    return sb.DesignResult(problem, np.array(problem.variables.start))
