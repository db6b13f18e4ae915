"""The floor the arm stands on, as a collision object of the ground (``mechanism: {floor: h}``,
:attr:`~springbalance.model.mechanism.Mechanism.floor`).

The floor is the world plane ``z = h`` [m]. It joins the arm's collision geometry
(:func:`~springbalance.model.collision.collision_geometry`) as a box of the ground whose top face is that plane
(:func:`floor_object`), so that the clearance check, the fit to the arm, the verification and the reports keep the
springs ``margin`` above it as they keep them from the links; a spring anchored on the ground or the arm's base is
exempt, as a spring is from its anchor bodies. The box is :data:`FLOOR_THICKNESS` deep, so that a spring below the
floor lies inside it (a negative distance, and a normal that lifts it), not clear beneath it.

A capsule's distance to the floor is measured in closed form (:func:`floor_contact`, :func:`capsule_height`): the
height of its axis' lower end above the plane less its radius, with the normal ``+z``. (GJK on a face parallel to
a capsule returns a witness normal tilted by milliradians, which a linearised row would carry along the spring.)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np
import pinocchio as pin

if TYPE_CHECKING:
    import coal

#: the name of the floor's collision object (:func:`floor_object`), which reports give in place of the ground body
#: that carries it: no URDF's object is named so (Pinocchio names them ``<link>_<index>``)
FLOOR = "floor"
#: half the floor slab's side [m] (it is centred under the world origin) and its thickness [m]: thick enough
#: that a spring below the floor is inside the slab (a negative distance, pushed up), not clear beneath it
FLOOR_HALF_SIDE, FLOOR_THICKNESS = 50.0, 20.0


def floor_object(height: float) -> pin.GeometryObject:
    """The floor as a collision object of the ground: a box whose top face is the world plane ``z = height``
    [m], :data:`FLOOR_HALF_SIDE` to each side of the origin and :data:`FLOOR_THICKNESS` deep."""
    import coal

    below = pin.SE3(np.eye(3), np.array([0.0, 0.0, height - FLOOR_THICKNESS / 2]))
    box = coal.Box(2 * FLOOR_HALF_SIDE, 2 * FLOOR_HALF_SIDE, FLOOR_THICKNESS)
    return pin.GeometryObject(FLOOR, 0, 0, below, box)


def with_floor(geometry: pin.GeometryModel, height: float | None) -> pin.GeometryModel:
    """``geometry`` with the floor at ``height`` [m] added (no floor: as it is)."""
    if height is not None:
        geometry.addGeometryObject(floor_object(height))
    return geometry


def floor_tops(objects: Sequence[pin.GeometryObject]) -> dict[int, float]:
    """The floor among ``objects`` (none or one) → the world height [m] of its top face."""
    return {
        index: float(obj.placement.translation[2] + obj.geometry.halfSide[2])
        for index, obj in enumerate(objects)
        if obj.name == FLOOR
    }


def floor_contact(
    start: np.ndarray, end: np.ndarray, radius: float, top: float, index: int
) -> tuple[float, int, np.ndarray, np.ndarray, np.ndarray]:
    """The capsule ``start``-``end`` of ``radius`` [m] (world) against the floor, object ``index`` with its top face
    at height ``top`` [m]: the fields of a :class:`~springbalance.model.collision.Contact`, the lower end's height
    above the floor less the radius, the witness points below that end, the normal up."""
    low = start if start[2] <= end[2] else end
    up = np.array([0.0, 0.0, 1.0])
    return float(low[2] - radius - top), index, low - radius * up, np.array([low[0], low[1], top]), up


def capsule_height(shape: coal.Capsule, placement: coal.Transform3s, top: float) -> float:
    """The distance [m] of a coal capsule (its axis along the placement's z) from the floor's top face at ``top``."""
    axis, centre = np.asarray(placement.getRotation())[:, 2], np.asarray(placement.getTranslation())
    lowest = centre[2] - abs(axis[2]) * shape.halfLength  # [m], the axis' lower end
    return float(lowest - shape.radius - top)
