"""The straight rods of a scene that move with the arm: a routed spring's cable segments, and the brackets that
hold anchors off their links.

- A cable (docs/model.md §3.9): a thin dark line from the spring's end over its pulleys, one cylinder per
  segment (:attr:`~springbalance.viz.tracks.SpringTrack.cable`).
- A bracket (:mod:`springbalance.model.brackets`): a grey rod from the anchor to the nearest point of its link's
  collision geometry, drawn for every anchor that stands off its link (:func:`add_brackets`), so that a spring
  is not seen floating beside the arm; the report warns of the long ones (``long_bracket``). In the frames
  where its straight line passes through another link (:func:`~springbalance.model.brackets.bracket_depths`) it
  is red, the colour of a spring below the clearance margin: there the bracket must go round.

Each rod is a unit cylinder (axis y) drawn once and placed per frame at its segment's middle, scaled to its
length (:func:`~springbalance.viz.tracks.rod_placement`). Lengths in m.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from springbalance.model.brackets import bracket_depths, spring_brackets
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.viz.colors import CLEARANCE_COLOR, CLEARANCE_RGB
from springbalance.viz.tracks import SpringTrack, rod_placement

#: a routed spring's cable: colour and radius [m]
CABLE_COLOR = 0x222222
CABLE_RADIUS = 0.0015
#: a bracket: colour (steel grey) and radius [m]
BRACKET_COLOR = 0x8C9099
BRACKET_RGB = (0x8C / 255, 0x90 / 255, 0x99 / 255)
BRACKET_RADIUS = 0.006


def add_brackets(
    tracks: list[SpringTrack],
    records: dict[str, dict],
    mechanism: Mechanism,
    kinematics: WorkspaceKinematics,
    configurations: np.ndarray,
) -> None:
    """Set :attr:`SpringTrack.brackets` and :attr:`SpringTrack.brackets_through` of every track with an anchor
    off its link: per end name, the world position of the bracket's foot per pose (N×3) and whether its straight
    line passes through another link there (N), from the springs' ``records`` (by name) and the path's
    ``kinematics`` and ``configurations`` (N×nq). Nothing is set without collision geometry."""
    named = {track.name: track for track in tracks if track.cable is None}
    held = {key: bracket for key, bracket in spring_brackets(mechanism, records.values()).items() if key[0] in named}
    for (name, end), (depths, _) in bracket_depths(mechanism, held, configurations).items():
        track = named[name]
        track.brackets = {
            **(track.brackets or {}),
            end: kinematics.body(held[(name, end)].body).points(held[(name, end)].foot),
        }
        track.brackets_through = {**(track.brackets_through or {}), end: depths > 0.0}


def _rods(spring: SpringTrack, frame: int) -> list[tuple[str, np.ndarray, np.ndarray, str | None]]:
    """``(node name, start, end, bracket)`` of each rod of ``spring`` at ``frame`` (world [m]); ``bracket``: the
    end name whose anchor a bracket holds, None for a cable segment."""
    rods: list[tuple[str, np.ndarray, np.ndarray, str | None]] = []
    if spring.cable is not None:
        for segment in range(spring.cable.shape[1] - 1):
            start, end = spring.cable[frame, segment], spring.cable[frame, segment + 1]
            rods.append((f"cables/{spring.name}/segment{segment}", start, end, None))
    anchors = spring.points_by_end()
    for end_name, feet in (spring.brackets or {}).items():
        rods.append((f"brackets/{spring.name}.{end_name}", feet[frame], anchors[end_name][frame], end_name))
    return rods


def draw_rods(root: Any, spring: SpringTrack, geometry: Any) -> None:
    """Draw the rods of ``spring`` at its first frame below ``root`` (``geometry``: ``meshcat.geometry``); the
    uuid of each bracket's mesh goes to :attr:`SpringTrack.rod_meshes` (its colour is animated)."""
    spring.rod_meshes = {}
    for name, start, end, bracket in _rods(spring, 0):
        colour = CABLE_COLOR if bracket is None else BRACKET_COLOR
        if bracket is not None and spring.brackets_through is not None and spring.brackets_through[bracket][0]:
            colour = CLEARANCE_COLOR  # through another link at the first pose: red from the start
        mesh = geometry.Mesh(
            geometry.Cylinder(1.0, CABLE_RADIUS if bracket is None else BRACKET_RADIUS),
            geometry.MeshPhongMaterial(color=colour),
        )
        root[name].set_object(mesh)
        if bracket is not None:
            spring.rod_meshes[name] = mesh.uuid
        rigid, length = rod_placement(start, end, spring.side)
        root[name].set_transform(rigid @ np.diag([1.0, length, 1.0, 1.0]))


def animate_rods(root: Any, spring: SpringTrack, frame: int) -> None:
    """Key frame ``frame`` of the rods of ``spring`` below ``root`` (a frame of the animation): placement, length
    and, for a bracket, its colour (red where it passes through another link)."""
    for name, start, end, bracket in _rods(spring, frame):
        rigid, length = rod_placement(start, end, spring.side)
        root[name].set_transform(rigid)
        root[name].set_property("scale", "vector3", [1.0, length, 1.0])
        if bracket is not None and spring.rod_meshes and spring.brackets_through:
            red = bool(spring.brackets_through[bracket][frame])
            colour = CLEARANCE_RGB if red else BRACKET_RGB
            root[name].set_property(f"{spring.rod_meshes[name]}.material.color", "color", list(colour))
