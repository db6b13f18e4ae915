"""Forces along a fixed direction in the scene (docs/model.md §3.11): an arrow at the anchor, along the force.

A :class:`~springbalance.springs.laws.directed.DirectedSpring` has no second end to draw a helix to:
it is drawn as an arrow (a shaft and a cone) from its anchor ``p`` along ``sign(f) u_w``, the
direction in which it pushes the anchor (``u_w`` the guide's direction in the world), its length
:data:`ARROW_LENGTH` [m] times ``|f| / max |f|`` over the frames (at least :data:`SHORTEST` of it),
in :data:`ARROW_COLOR`.
"""

from __future__ import annotations

import dataclasses
import html
from typing import Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.springs.laws.directed import DirectedSpring
from springbalance.viz.helix import placement
from springbalance.viz.meshcat_import import import_meshcat

#: the drawn length of the largest force [m]
ARROW_LENGTH = 0.15
#: the shortest arrow, as a fraction of ARROW_LENGTH (a vanishing force still shows its direction)
SHORTEST = 0.1
ARROW_COLOR = 0x1F5FBF
SHAFT_RADIUS, HEAD_RADIUS, HEAD_FRACTION = 0.004, 0.012, 0.25  # [m], [m], [1]


@dataclasses.dataclass
class ForceArrow:
    """One directed force over the frames: anchor positions (N×3) [m], unit directions of the push
    on the anchor (N×3), forces ``f`` (N) [N]."""

    name: str
    starts: np.ndarray
    directions: np.ndarray
    forces: np.ndarray

    def scales(self) -> np.ndarray:
        """The arrow's length per frame as a fraction of :data:`ARROW_LENGTH`."""
        largest = float(np.max(np.abs(self.forces))) if self.forces.size else 0.0
        fraction = np.abs(self.forces) / largest if largest > 0 else np.ones_like(self.forces)
        return np.maximum(fraction, SHORTEST)

    def rigid_transform(self, frame: int) -> np.ndarray:
        """The arrow's placement at ``frame``: its local y axis along the push, its origin at the anchor."""
        return placement(_y_along(self.directions[frame]), self.starts[frame])

    def transform(self, frame: int) -> np.ndarray:
        """:meth:`rigid_transform` with the arrow's length: its local y axis scaled by :meth:`scales`."""
        return self.rigid_transform(frame) @ np.diag([1.0, float(self.scales()[frame]), 1.0, 1.0])


def force_arrows(
    design: EvaluatedDesign, forces: np.ndarray, kinematics: WorkspaceKinematics
) -> tuple[list[ForceArrow], list[int]]:
    """The arrows of the directed springs of ``design`` over the poses of ``kinematics``, and their columns
    (``forces``: the springs' generalised forces per pose, N×k [N])."""
    arrows, columns = [], []
    for column, (spring, record) in enumerate(zip(design.problem.springs, design.springs)):
        if not isinstance(spring, DirectedSpring):
            continue
        starts = kinematics.body(record["a"]["body"]).points(np.array(record["a"]["point"], dtype=float))
        guide = kinematics.body(spring.guide)
        unit = guide.points(spring.direction) - guide.points(np.zeros(3))  # u_w per pose
        force = np.asarray(forces[:, column], dtype=float)
        directions = np.where(force[:, None] < 0, -unit, unit)
        arrows.append(ForceArrow(record["name"], np.atleast_2d(starts), directions, force))
        columns.append(column)
    return arrows, columns


def draw_arrows(root: Any, arrows: list[ForceArrow]) -> None:
    """Draw each arrow at the first frame below ``root``."""
    mg = import_meshcat().geometry
    for arrow in arrows:
        node = root["arrows"][arrow.name]
        material = mg.MeshPhongMaterial(color=ARROW_COLOR)
        shaft = ARROW_LENGTH * (1 - HEAD_FRACTION)
        node["shaft"].set_object(mg.Cylinder(shaft, SHAFT_RADIUS), material)
        node["shaft"].set_transform(placement(np.eye(3), [0.0, shaft / 2, 0.0]))
        head = ARROW_LENGTH * HEAD_FRACTION
        node["head"].set_object(mg.Cylinder(head, radiusTop=0.0, radiusBottom=HEAD_RADIUS), material)
        node["head"].set_transform(placement(np.eye(3), [0.0, shaft + head / 2, 0.0]))
        node.set_transform(arrow.transform(0))


def animate_arrow(root: Any, arrow: ForceArrow, frame: int) -> None:
    """Key frame ``frame`` of ``arrow`` below ``root`` (a frame of the animation): placement and length."""
    node = root["arrows"][arrow.name]
    node.set_transform(arrow.rigid_transform(frame))
    node.set_property("scale", "vector3", [1.0, float(arrow.scales()[frame]), 1.0])


def _y_along(direction: np.ndarray) -> np.ndarray:
    """A rotation whose second column (the local y axis, meshcat's cylinder axis) is ``direction``."""
    y = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    helper = np.eye(3)[int(np.argmin(np.abs(y)))]
    x = np.cross(y, helper)
    x /= np.linalg.norm(x)
    return np.column_stack([x, y, np.cross(x, y)])


def arrows_legend_html(arrows: list[str], skipped: list[str], position: str = "fixed") -> str:
    """The legend of a scene whose springs are all directed (arrows) or in joints (not drawn): no tension scale,
    what the arrows are and which springs are not drawn, by name (``position`` as in
    :meth:`~springbalance.viz.colors.ColorScale.legend_html`)."""
    lines = []
    if arrows:
        swatch = f'<span style="color:#{ARROW_COLOR:06x};font-weight:bold">&#8593;</span>'
        lines.append(f"{swatch} force along a fixed direction: {html.escape(', '.join(arrows))}")
    if skipped:
        lines.append(f"not drawn (they act in a joint): {html.escape(', '.join(skipped))}")
    body = "".join(f"<div>{line}</div>" for line in lines) or "<div>no springs drawn</div>"
    return (
        f'<div id="springbalance-legend" style="position:{position};left:8px;top:8px;max-width:260px;padding:6px 14px;'
        f'background:rgba(255,255,255,0.85);border-radius:4px;font:12px sans-serif;color:#222;z-index:10">{body}</div>'
    )
