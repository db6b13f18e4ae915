"""The two zero-free-length springs on urdf/two_link_planar_collision.urdf whose in-plane optimum crosses the
folded-back link2: the clearance tests (design/test_clearance_constraint.py,
design/test_clearance_fit_infeasible.py) move them out of the arm's plane."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import springbalance as sb
from springbalance.design.solvers import solve_problem

URDF = Path(__file__).resolve().parents[1] / "urdf"


def crossing_springs(width: float) -> list[sb.ZeroFreeLengthSpring]:
    """A ground→link1 spring whose in-plane optimum crosses the folded-back link2, and a link1→link2 spring;
    the anchors may leave the arm's plane by ``width`` [m] (0: in the plane)."""
    return [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([-0.1, -width, 0.2], [0.1, width, 0.4], init=[0, 0, 0.3])),
            sb.Anchor("link1", sb.Free([0.3, -width, -0.05], [0.5, width, 0.05], init=[0.4, 0, 0])),
            stiffness=sb.Free(0, 5000),
            name="s1",
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("link1", sb.Free([-0.1, -width, -0.1], [0.45, width, 0.1], init=[0.2, 0, 0])),
            sb.Anchor("link2", sb.Free([0.02, -width, -0.05], [0.4, width, 0.05], init=[0.2, 0, 0])),
            stiffness=sb.Free(0, 5000),
            name="s2",
        ),
    ]


def crossing_case(margin: float, check_samples: int = 64) -> tuple[sb.DesignProblem, np.ndarray]:
    """The fit's case: the springs with anchors that may leave the arm's plane by 0.1 m, kept ``margin`` [m] clear
    (checked on ``check_samples`` poses), over 128 Sobol poses; and the in-plane optimum of the multi-start (4 starts;
    it carries the elbow beyond the bare arm's peak, which the pipeline would then hold), whose first spring passes
    through link2, as the fit's start."""
    arm = sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")
    workspace = sb.Workspace.sobol(arm, n=128, seed=0)
    in_plane = sb.DesignProblem(arm, workspace, crossing_springs(0.0))
    values = dict(zip(in_plane.variables.names, solve_problem(in_plane, starts=4, progress=False).x))
    clearance = sb.Clearance(margin=margin, check_samples=check_samples)
    problem = sb.DesignProblem(arm, workspace, crossing_springs(0.1), clearance=clearance)
    start = np.array([values.get(name, 0.0) for name in problem.variables.names])
    return problem, start
