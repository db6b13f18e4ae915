"""The surfaces of a body's collision geometry, for anchors mounted on a link (``on: collision``): the
signed distance from a point in the body's frame to the union of the body's objects (meshes as their convex
hulls), with the closest surface point and the outward normal (:func:`surface_distance`).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model.collision import hull
from springbalance.model.mechanism import Mechanism


def body_objects(mechanism: Mechanism, geometry: pin.GeometryModel, body: str) -> list:
    """The collision objects carried by ``body`` (or by links welded to it by fixed joints are *not*
    included: only the objects whose parent frame is the body's own link frame)."""
    return [obj for obj in geometry.geometryObjects if mechanism.model.frames[obj.parentFrame].name == body]


def surface_distance(
    mechanism: Mechanism, geometry: pin.GeometryModel, body: str, point: np.ndarray
) -> tuple[float, np.ndarray, np.ndarray]:
    """Signed distance [m] from ``point`` (body frame, [m]) to the union of ``body``'s collision objects,
    the closest surface point (body frame) and the unit outward normal there (body frame).

    Meshes count as their convex hulls. Raises :class:`InputError` when ``body`` has no collision geometry.
    """
    import coal

    objects = body_objects(mechanism, geometry, body)
    if not objects:
        raise InputError(
            f"body {body!r} has no collision geometry in the URDF, so an anchor cannot be mounted "
            "on it with 'on: collision'; give a box, point, segment or plane instead"
        )
    frame = mechanism.model.frames[mechanism.frame_id(body)].placement  # the body frame in its joint's frame
    request = coal.DistanceRequest()
    request.enable_signed_distance = True
    probe = coal.Sphere(1e-9)
    best = None
    for obj in objects:
        shape = hull(obj.geometry)
        local = frame.actInv(obj.placement)  # the object in the body frame
        result = coal.DistanceResult()
        distance = coal.distance(
            probe,
            coal.Transform3s(np.eye(3), np.asarray(point, dtype=float)),
            shape,
            coal.Transform3s(np.array(local.rotation), np.array(local.translation)),
            request,
            result,
        )
        distance = float(distance) + 1e-9
        if best is None or distance < best[0]:
            best = (distance, np.array(result.getNearestPoint2()), -np.array(result.normal))
    assert best is not None  # objects is not empty (checked above)
    return best
