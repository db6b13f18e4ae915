"""The two-link arm of urdf/two_link_planar.urdf with one extension spring per joint, which several tests share."""

from __future__ import annotations

import springbalance as sb

URDF = "urdf/two_link_planar.urdf"


def spring_per_joint() -> list[sb.ExtensionSpring]:
    """One extension spring ground → link1 (the shoulder only) and one link1 → link2 (the elbow only), anchors free in
    boxes of the arm's plane [m], stiffness in [0, 5000] N/m and free length in [0, 0.5] m."""
    return [
        sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free([-0.1, 0, 0.02], [0.1, 0, 0.3])),
            sb.Anchor("link1", sb.Free([0.05, 0, -0.05], [0.45, 0, 0.05])),
            stiffness=sb.Free(0, 5000),
            free_length=sb.Free(0.0, 0.5),
        ),
        sb.ExtensionSpring(
            sb.Anchor("link1", sb.Free([0.0, 0, -0.1], [0.45, 0, 0.1])),
            sb.Anchor("link2", sb.Free([-0.1, 0, -0.05], [0.3, 0, 0.05])),
            stiffness=sb.Free(0, 5000),
            free_length=sb.Free(0.0, 0.5),
        ),
    ]


def crossing_spring(**options: float) -> sb.ExtensionSpring:
    """One extension spring "s1" from the ground to link2, across both joints: anchors free in boxes of the arm's
    plane [m], stiffness in [0, 5000] N/m, free length in [0, 0.8] m; ``options`` such as ``max_length`` [m]."""
    return sb.ExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.1, 0, 0.02], [0.1, 0, 0.4])),
        sb.Anchor("link2", sb.Free([-0.1, 0, -0.05], [0.3, 0, 0.05])),
        name="s1",
        stiffness=sb.Free(0, 5000),
        free_length=sb.Free(0.0, 0.8),
        **options,
    )
