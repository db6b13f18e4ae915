"""The parallelograms that realise the pseudo-bases (:mod:`springbalance.model.pseudo_bases`), drawn as rods.

A pseudo-base at joint J keeps the world's orientation because a chain of parallelograms carries it from the
ground: one per moving joint between the root and J (seed 004 ch. 4). Along the segment from each such joint's
origin ``p_a`` to the next one's ``p_b`` (a side that the arm's link provides), the parallelogram has the
opposite bar ``p_a + u → p_b + u`` and the two cranks ``p_a → p_a + u`` and ``p_b → p_b + u``, with ``u`` a
vector fixed in the world (:data:`CRANK` [m] up, longer for each further pseudo-base so that they do not overlap):
the cranks are world-oriented, as the pseudo-bases are. Each rod is a thin cylinder placed per animation frame.
A pseudo-base that keeps only the vertical (``keep: vertical``) needs no parallelogram across the arm's leading
vertical-axis joints (its chain does not undo them): its path starts at the first joint its chain undoes.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin

from springbalance.model.mechanism import Mechanism
from springbalance.viz.helix import placement, spring_rotation
from springbalance.viz.meshcat_import import import_meshcat

__all__ = ["CRANK", "PARALLELOGRAM_COLOR", "draw_parallelograms", "parallelogram_rods", "place_parallelograms"]

#: the length [m] of the first pseudo-base's cranks (world +z); each further pseudo-base adds as much again
CRANK = 0.05
#: colour and radius [m] of the rods
PARALLELOGRAM_COLOR = 0x8A6D3B
ROD_RADIUS = 0.004


def parallelogram_rods(mechanism: Mechanism, configurations: np.ndarray) -> dict[str, np.ndarray]:
    """Per pseudo-base body, its rods over the poses: F×R×2×3 (start and end [m], world) for R rods."""
    model = mechanism.model
    data = model.createData()
    ids = {base.body: _joint_path(model, base.joint, base.body) for base in mechanism.pseudo_bases}
    rods = {body: np.zeros((len(configurations), 3 * (len(path) - 1), 2, 3)) for body, path in ids.items()}
    for frame, q in enumerate(configurations):
        pin.forwardKinematics(model, data, q)
        for index, (body, path) in enumerate(ids.items()):
            crank = np.array([0.0, 0.0, CRANK * (index + 1)])
            points = [data.oMi[joint].translation for joint in path]
            for slot, (start, end) in enumerate(zip(points, points[1:])):
                rods[body][frame, 3 * slot : 3 * slot + 3] = [
                    (start + crank, end + crank),
                    (start, start + crank),
                    (end, end + crank),
                ]
    return rods


def _joint_path(model: pin.Model, joint: str, body: str) -> list[int]:
    """The moving joints from the root to ``joint`` that the chain of pseudo-base ``body`` undoes (its ancestors
    with a mimic joint ``<body>__undo_<name>``), then ``joint`` itself, as Pinocchio joint ids."""
    path = [model.getJointId(joint)]
    while model.parents[path[0]] > 0:
        path.insert(0, model.parents[path[0]])
    names = set(model.names)
    return [index for index in path[:-1] if f"{body}__undo_{model.names[index]}" in names] + path[-1:]


def _transform(rod: np.ndarray) -> np.ndarray:
    """The node transform of a unit cylinder (axis y) stretched over ``rod`` (start, end)."""
    direction = rod[1] - rod[0]
    length = float(np.linalg.norm(direction))
    rotation = spring_rotation(direction if length > 0 else np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.3, 0.1]))
    y_to_z = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    return placement(rotation @ y_to_z, rod.mean(axis=0)) @ np.diag([1.0, max(length, 1e-9), 1.0, 1.0])


def draw_parallelograms(root: Any, rods: dict[str, np.ndarray]) -> None:
    """Draw every rod at the first pose below ``root["parallelograms"]``."""
    mg = import_meshcat().geometry
    for body, track in rods.items():
        for index in range(track.shape[1]):
            node = root["parallelograms"][body][f"rod{index}"]
            node.set_object(mg.Cylinder(1.0, ROD_RADIUS), mg.MeshPhongMaterial(color=PARALLELOGRAM_COLOR))
            node.set_transform(_transform(track[0, index]))


def place_parallelograms(root: Any, rods: dict[str, np.ndarray], frame: int) -> None:
    """Key frame ``frame`` of every rod below ``root["parallelograms"]`` (a frame of the animation)."""
    for body, track in rods.items():
        for index in range(track.shape[1]):
            root["parallelograms"][body][f"rod{index}"].set_transform(_transform(track[frame, index]))
