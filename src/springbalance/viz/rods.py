"""The straight rods of a scene that move with the arm: a routed spring's cable segments, and the brackets that
hold anchors off their links.

- A cable (docs/model.md §3.9): a thin dark line from the spring's end over its pulleys, one cylinder per
  segment (:attr:`~springbalance.viz.tracks.SpringTrack.cable`).
- A bracket (:mod:`springbalance.model.brackets`): a grey rod from the anchor to the nearest point of its link's
  collision geometry, drawn for every anchor that stands off its link (:func:`add_brackets`), so that a spring
  is not seen floating beside the arm; the report warns of the long ones (``long_bracket``).

Each rod is a unit cylinder (axis y) drawn once and placed per frame at its segment's middle, scaled to its
length (:func:`~springbalance.viz.tracks.rod_placement`). Lengths in m.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from springbalance.model.brackets import spring_brackets
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.viz.tracks import SpringTrack, rod_placement

#: a routed spring's cable: colour and radius [m]
CABLE_COLOR = 0x222222
CABLE_RADIUS = 0.0015
#: a bracket: colour (steel grey) and radius [m]
BRACKET_COLOR = 0x8C9099
BRACKET_RADIUS = 0.006


def add_brackets(
    tracks: list[SpringTrack], records: dict[str, dict], mechanism: Mechanism, kinematics: WorkspaceKinematics
) -> None:
    """Set :attr:`SpringTrack.brackets` of every track with an anchor off its link: the world position of the
    bracket's foot per pose (N×3) by end name, from the springs' ``records`` (by name) and the path's
    ``kinematics``. Nothing is set without collision geometry."""
    for (name, end), held in spring_brackets(mechanism, records.values()).items():
        track = next((track for track in tracks if track.name == name), None)
        if track is not None and track.cable is None:
            feet = kinematics.body(held.body).points(held.foot)
            track.brackets = {**(track.brackets or {}), end: feet}


def _rods(spring: SpringTrack, frame: int) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """``(node name, start, end)`` of each rod of ``spring`` at ``frame`` (world [m])."""
    rods = []
    if spring.cable is not None:
        for segment in range(spring.cable.shape[1] - 1):
            rods.append(
                (
                    f"cables/{spring.name}/segment{segment}",
                    spring.cable[frame, segment],
                    spring.cable[frame, segment + 1],
                )
            )
    anchors = spring.points_by_end()
    for end, feet in (spring.brackets or {}).items():
        rods.append((f"brackets/{spring.name}.{end}", feet[frame], anchors[end][frame]))
    return rods


def draw_rods(root: Any, spring: SpringTrack, geometry: Any) -> None:
    """Draw the rods of ``spring`` at its first frame below ``root`` (``geometry``: ``meshcat.geometry``)."""
    for name, start, end in _rods(spring, 0):
        bracket = name.startswith("brackets/")
        node = root[name]
        node.set_object(
            geometry.Cylinder(1.0, BRACKET_RADIUS if bracket else CABLE_RADIUS),
            geometry.MeshPhongMaterial(color=BRACKET_COLOR if bracket else CABLE_COLOR),
        )
        rigid, length = rod_placement(start, end, spring.side)
        node.set_transform(rigid @ np.diag([1.0, length, 1.0, 1.0]))


def animate_rods(root: Any, spring: SpringTrack, frame: int) -> None:
    """Key frame ``frame`` of the rods of ``spring`` below ``root`` (a frame of the animation)."""
    for name, start, end in _rods(spring, frame):
        rigid, length = rod_placement(start, end, spring.side)
        root[name].set_transform(rigid)
        root[name].set_property("scale", "vector3", [1.0, length, 1.0])
