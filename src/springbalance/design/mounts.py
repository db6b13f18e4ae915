"""Anchors mounted ``on: collision``: their regions and the check that they can reach their surface.

An anchor ``on: collision`` lies ``offset`` [m] outside its body's collision surface (the union of the
body's objects; meshes as their convex hulls). Without a box of its own, its region is the bounding box
of those objects grown by ``offset`` + 5 mm (:func:`resolve_mounts`). The rows that hold it on the
surface during the solve are :func:`springbalance.design.clearance_rows.mount_rows`.
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from springbalance.errors import InputError
from springbalance.model.collision import collision_geometry, hull
from springbalance.model.mechanism import Mechanism
from springbalance.model.surfaces import body_objects, surface_distance
from springbalance.springs.laws import Spring
from springbalance.springs.params import Free

#: Half-width [m] of the band the mounting rows keep an anchor in around its offset surface.
MOUNT_TOLERANCE = 2e-4
#: An anchor counts as on its surface when within this distance [m] of it.
MOUNT_ACCEPT = 5e-4


# ====================================================================== mounting
def mounted_anchors(springs: list[Spring]) -> list[tuple[Any, str, Any]]:
    """``(spring, end, anchor)`` of every anchor mounted ``on: collision``."""
    return [
        (spring, end, anchor)
        for spring in springs
        for end, anchor in spring.anchors.items()
        if getattr(anchor, "mount", None) == "collision"
    ]


def resolve_mounts(mechanism: Mechanism, springs: list[Spring]) -> list[Spring]:
    """The springs with every ``on: collision`` anchor given a region: its box, or, without one, the
    bounding box of its body's collision objects grown by ``offset`` + 5 mm. Springs with such
    anchors are copied (the caller's objects are not changed)."""
    if not mounted_anchors(springs):
        return springs
    geometry = collision_geometry(mechanism)
    resolved = []
    for spring in springs:
        if not mounted_anchors([spring]):
            resolved.append(spring)
            continue
        spring = copy.copy(spring)
        for end, anchor in spring.anchors.items():
            if getattr(anchor, "mount", None) != "collision" or anchor.point is not None:
                continue
            lower, upper = body_bounds(mechanism, geometry, anchor.body)
            grown = anchor.offset + 0.005
            anchor = copy.copy(anchor)
            anchor.point = Free(lower - grown, upper + grown)
            setattr(spring, end, anchor)  # two-point springs keep their ends as attributes a and b
        resolved.append(spring)
    return resolved


def body_bounds(mechanism: Mechanism, geometry: Any, body: str) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounds (body frame, [m]) of ``body``'s collision objects."""
    import coal  # noqa: F401  (the hull and AABB below are coal objects: a clear ImportError here)

    objects = body_objects(mechanism, geometry, body)
    if not objects:
        raise InputError(
            f"body {body!r} has no collision geometry in the URDF, so an anchor cannot be mounted "
            "on it with 'on: collision'; give a box, point, segment or plane instead"
        )
    frame = mechanism.model.frames[mechanism.frame_id(body)].placement
    lows, highs = [], []
    for obj in objects:
        shape = hull(obj.geometry)
        shape.computeLocalAABB()
        box = shape.aabb_local
        local = frame.actInv(obj.placement)
        corners = np.array([[box.min_[i] if (k >> i) & 1 == 0 else box.max_[i] for i in range(3)] for k in range(8)])
        world = corners @ np.array(local.rotation).T + np.array(local.translation)
        lows.append(world.min(axis=0))
        highs.append(world.max(axis=0))
    return np.min(lows, axis=0), np.max(highs, axis=0)


def check_mounts(mechanism: Mechanism, springs: list[Spring]) -> list[tuple[Any, str, Any]]:
    """Check that every ``on: collision`` anchor's box reaches its offset surface; return the mounted anchors.

    Raises:
        InputError: the body has no collision geometry, or no point of the box lies ``offset``
            from the body's collision surface (names the spring, end, body and the distances found).
    """
    mounts = mounted_anchors(springs)
    if not mounts:
        return []
    geometry = collision_geometry(mechanism)
    for spring, end, anchor in mounts:
        region = anchor.region()
        grid = np.linspace(0.0, 1.0, 7)
        axes = np.meshgrid(
            *[region.lower[i] + (region.upper[i] - region.lower[i]) * grid for i in range(region.basis.shape[1])],
            indexing="ij",
        )
        coordinates = np.stack([axis.reshape(-1) for axis in axes], axis=1) if axes else np.zeros((1, 0))
        distances = (
            np.array([surface_distance(mechanism, geometry, anchor.body, region.point(c))[0] for c in coordinates])
            - anchor.offset
        )
        if distances.min() > MOUNT_ACCEPT or distances.max() < -MOUNT_ACCEPT:
            raise InputError(
                f"spring {spring.name!r} end {end}: no point of its box on {anchor.body!r} lies {anchor.offset * 1e3:g} mm "
                f"from the body's collision surface (the box is {distances.min() * 1e3 + anchor.offset * 1e3:.1f} to "
                f"{distances.max() * 1e3 + anchor.offset * 1e3:.1f} mm from it): no anchor can reach the mounting surface"
            )
    return mounts
