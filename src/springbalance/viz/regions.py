"""The free region of each anchor (:class:`RegionShape`): a box, a segment or a plane rectangle of
:mod:`springbalance.springs.params`, in its body's frame, and its geometry for drawing (a translucent
shape and its edges) and for framing (the points whose convex hull it is). Lengths in m.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Iterable

import numpy as np

from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.springs.params import Free, Plane, Segment
from springbalance.viz.helix import spring_rotation
from springbalance.viz.meshcat_import import import_meshcat

REGION_COLOR = 0x8C6BB1
REGION_OPACITY = 0.12
#: Thickness [m] of a box side with no width, and of the rods and sheets that show segments and rectangles.
REGION_THICKNESS = 0.004


@dataclasses.dataclass
class RegionShape:
    """The free region of one anchor, in its body's frame.

    ``kind`` is ``"box"`` (centre and size [m]), ``"segment"`` (from ``start`` to ``end``
    [m]) or ``"plane"`` (the four corners [m] of the rectangle). ``placements`` holds
    the body's world placement per pose (N×4×4).
    """

    spring: str
    end: str
    body: str
    kind: str
    corners: np.ndarray
    placements: np.ndarray


def anchor_regions(springs: Iterable[Any], kinematics: WorkspaceKinematics, size: int) -> list[RegionShape]:
    """The free region of every anchor of ``springs`` that has one, placed on its body over the ``size``
    poses of ``kinematics``. Anchors mounted on a link's own surface (``mount="collision"``) are left out:
    the link is the mounting surface drawn."""
    regions = []
    for spring in springs:
        for end, anchor in spring_anchors(spring).items():
            if getattr(anchor, "mount", None) == "collision":
                continue  # mounted on the link's own surface: the link is the mounting surface drawn
            corners = region_corners(anchor.point)
            if corners is None:
                continue
            kind, points = corners
            body = kinematics.body(anchor.body)
            placements = np.zeros((size, 4, 4))
            placements[:, :3, :3] = body.rotation
            placements[:, :3, 3] = body.translation
            placements[:, 3, 3] = 1.0
            regions.append(RegionShape(spring.name, end, anchor.body, kind, points, placements))
    return regions


def spring_anchors(spring: Any) -> dict:
    """The spring's anchors by end name (none for a spring that acts in a joint)."""
    anchors = getattr(spring, "anchors", None)
    if isinstance(anchors, dict):
        return anchors
    return {end: getattr(spring, end) for end in ("a", "b") if hasattr(spring, end)}


def region_corners(point: Any) -> tuple[str, np.ndarray] | None:
    """``(kind, points)`` describing an anchor's free region in the body frame, or None if fixed."""
    if isinstance(point, Segment):
        lower, upper = float(point.bounds.lower), float(point.bounds.upper)
        direction = point.end - point.start
        return "segment", np.array([point.start + lower * direction, point.start + upper * direction])
    if isinstance(point, Plane):
        (s0, t0), (s1, t1) = point.bounds.lower, point.bounds.upper
        corners = [point.origin + s * point.u + t * point.v for s, t in ((s0, t0), (s1, t0), (s1, t1), (s0, t1))]
        return "plane", np.array(corners)
    if isinstance(point, Free):
        if not np.any(point.upper > point.lower):
            return None
        return "box", np.array([point.lower, point.upper])
    return None


def region_mesh(region: RegionShape) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices and faces (body coordinates) of the region's solid (a box, or a thin rod or sheet
    where flat, :data:`REGION_THICKNESS` thick) and the end points of its edges (2E×3, pairs for
    ``LineSegments``)."""
    thickness = REGION_THICKNESS
    if region.kind == "box":
        lower, upper = region.corners
        size = np.maximum(upper - lower, thickness)
        vertices, faces = _box_mesh((lower + upper) / 2, size, np.eye(3))
        edges = vertices[_BOX_EDGES.ravel()]
    elif region.kind == "segment":
        start, end = region.corners
        axis = end - start
        length = float(np.linalg.norm(axis))
        rotation = spring_rotation(axis, np.eye(3)[int(np.argmin(np.abs(axis)))]) if length > 0 else np.eye(3)
        vertices, faces = _box_mesh(
            (start + end) / 2, np.array([thickness, thickness, max(length, thickness)]), rotation
        )
        edges = np.array([start, end])
    else:
        c = region.corners
        normal = np.cross(c[1] - c[0], c[3] - c[0])
        normal = thickness / 2 * normal / np.linalg.norm(normal)
        vertices = np.vstack([c - normal, c + normal])
        faces = np.array(
            [
                [0, 1, 2],
                [0, 2, 3],
                [4, 6, 5],
                [4, 7, 6],
                [0, 4, 5],
                [0, 5, 1],
                [1, 5, 6],
                [1, 6, 2],
                [2, 6, 7],
                [2, 7, 3],
                [3, 7, 4],
                [3, 4, 0],
            ]
        )
        edges = c[[0, 1, 1, 2, 2, 3, 3, 0]]
    return vertices, faces, edges


def region_geometry(region: RegionShape) -> tuple[Any, np.ndarray]:
    """Meshcat geometry (``TriangularMeshGeometry``) of :func:`region_mesh` and its edges (2E×3, float32)."""
    vertices, faces, edges = region_mesh(region)
    return import_meshcat().geometry.TriangularMeshGeometry(vertices, faces), np.asarray(edges, dtype=np.float32)


def region_points(region: RegionShape) -> np.ndarray:
    """Points (body frame) [m] whose convex hull is the region: a box's 8 corners, a segment's ends,
    a rectangle's 4 corners."""
    if region.kind == "box":
        lower, upper = region.corners
        return np.array(
            [
                [(lower, upper)[i][0], (lower, upper)[j][1], (lower, upper)[k][2]]
                for i in (0, 1)
                for j in (0, 1)
                for k in (0, 1)
            ]
        )
    return np.asarray(region.corners, dtype=float)


#: vertex pairs of the 12 edges of :func:`_box_mesh` (vertex index bits: x, y, z)
_BOX_EDGES = np.array([[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]])


def _box_mesh(center: np.ndarray, size: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (8×3) and triangles (12×3) of a box of ``size`` [m] about ``center``, turned by ``rotation``."""
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    vertices = center + (signs * size / 2) @ np.asarray(rotation).T
    faces = np.array(
        [
            [0, 1, 3],
            [0, 3, 2],
            [4, 6, 7],
            [4, 7, 5],
            [0, 4, 5],
            [0, 5, 1],
            [2, 3, 7],
            [2, 7, 6],
            [0, 2, 6],
            [0, 6, 4],
            [1, 5, 7],
            [1, 7, 3],
        ]
    )
    return vertices, faces
