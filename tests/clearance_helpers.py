"""The two zero-free-length springs on urdf/two_link_planar_collision.urdf whose in-plane optimum crosses the
folded-back link2: the clearance tests (design/test_clearance_constraint.py,
design/test_clearance_fit_infeasible.py) move them out of the arm's plane."""

from __future__ import annotations

import springbalance as sb


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
