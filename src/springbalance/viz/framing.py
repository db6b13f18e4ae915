r"""How the camera frames a scene: the arm and its springs at the shown pose as large as the view allows,
while every pose of the path (what the animation and the pose slider show) stays in view.

**What is framed.** Per pose of the path: the eight corners of each visual shape's local bounding box
(for the two-link arm's boxes, the boxes themselves; for a mesh, a box around it), each joint's origin,
and each spring's two ends with the cube around the sphere of its coil's radius plus its wire's; of these
points, the vertices of their convex hull (:func:`view_points`).

**For one line of sight** ``d`` (unit, from the target towards the camera), the camera stands at
``c = t + D d`` and looks at ``t``, world z up, with the scene's perspective (vertical field of view :data:`~springbalance.viz.camera.SCENE_FOV`,
``tan(fov / 2) = h``) in a view :data:`~springbalance.viz.camera.CAMERA_ASPECT` wide (``a``). A point ``p`` at
depth ``z = (p − c)·(−d)`` lands at ``X = (p − c)·right / (z h a)``, ``Y = (p − c)·up / (z h)`` (the view spans
−1…1). :func:`fit_view` takes the
smallest ``D`` (bisection) for which every point of every pose lies within :data:`VIEW_FILL` of the view's half
width and half height, then moves ``t`` across the line of sight so that their projected box is centred, and
fits ``D`` again (:data:`FIT_ROUNDS` times). Where the points leave room across the view, the view moves so
that they keep to its left, away from the pose slider's panel at the bottom right (as far as every point stays
in view: nearer points move further). Last, the target slides along the line of sight (the view
does not change) to the point nearest the middle of the points' box: meshcat's orbit controls turn the view
about it.

**The line of sight** (:func:`best_view`) is the one, on a grid of azimuths (every 15°) and elevations 20°–45°
above the horizon (a three-quarter view from above), that maximises the share of the view the shown pose's box
(its projected width share times its height share) covers, among those where its larger side covers at least
:data:`SHOWN_SIDE` of the view when some do. A planar arm (its points spread in a plane) is seen within
:data:`PLANE_TILT` of the plane's normal, never edge-on. Shares within :data:`TIE` of each other count as
equal: the direction met first wins, in order of closeness to the default (1, −1.3, 0.8). Lengths in m.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import numpy as np
import pinocchio as pin
from scipy.spatial import ConvexHull, QhullError

from springbalance.viz.camera import CAMERA_ASPECT, SCENE_FOV
from springbalance.viz.tracks import SpringTrack

#: Share of the view's half width and half height that the poses of the path may fill.
VIEW_FILL = 0.96
#: The shown pose's larger side should cover at least this share of the view.
SHOWN_SIDE = 0.5
#: Rounds of fitting the distance and centring the target.
FIT_ROUNDS = 4
#: Lines of sight tried: azimuths [deg] and elevations [deg] above the horizon.
AZIMUTHS, ELEVATIONS = tuple(range(0, 360, 15)), (20.0, 30.0, 40.0, 45.0)
#: Largest angle [deg] between the line of sight and a planar arm's normal.
PLANE_TILT = 50.0
#: Relative difference of the covered shares below which two lines of sight count as equal.
TIE = 0.02
#: The line of sight preferred among equals (from the arm's middle towards the camera).
DEFAULT_DIRECTION = np.array([1.0, -1.3, 0.8]) / np.linalg.norm([1.0, -1.3, 0.8])


class View(NamedTuple):
    """Where the camera stands (``position``, world [m]), what it looks at (``target``, world [m]) and how much
    of the view the shown pose covers (``share``: its projected box's width and height over the view's)."""

    target: np.ndarray
    position: np.ndarray
    share: tuple[float, float]


def view_points(
    springs: list[SpringTrack],
    model: pin.Model,
    visual_model: pin.GeometryModel,
    configurations: np.ndarray,
    frames: slice = slice(None),
) -> np.ndarray:
    """Points (K×3) [m] whose convex hull holds what is drawn at the poses ``configurations[frames]`` (see the
    module documentation; a spring's end counts as the corners of the cube around its sphere); only the hull's
    vertices are kept (the extremes of a projection are among them)."""
    corners = []
    for geometry in visual_model.geometryObjects:
        try:
            geometry.geometry.computeLocalAABB()
            box = geometry.geometry.aabb_local
            bounds = np.array([box.min_, box.max_])
        except (AttributeError, RuntimeError):
            bounds = np.zeros((2, 3))
        corners.append(np.array([bounds[pick, [0, 1, 2]] for pick in itertools.product((0, 1), repeat=3)]))
    cube = np.array(list(itertools.product((-1.0, 1.0), repeat=3)))
    data, visual_data = model.createData(), visual_model.createData()
    points = []
    for q in configurations[frames]:
        pin.forwardKinematics(model, data, q)
        pin.updateGeometryPlacements(model, data, visual_model, visual_data)
        for index, box in enumerate(corners):
            points.append(box @ visual_data.oMg[index].rotation.T + visual_data.oMg[index].translation)
        points.append(np.array([data.oMi[joint].translation for joint in range(model.njoints)]))
    for spring in springs:
        reach = spring.coil_radius + spring.wire_radius
        for ends in (spring.starts, spring.ends, *spring.points_by_end().values()):
            points.append((ends[frames][:, None, :] + reach * cube).reshape(-1, 3))
    return _hull(np.vstack(points))


def _hull(points: np.ndarray) -> np.ndarray:
    """The vertices of the convex hull of ``points`` (all of them when they span no volume)."""
    try:
        return points[ConvexHull(points).vertices]
    except QhullError:
        return points


def _axes(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The camera's forward, right and up unit vectors for the line of sight ``direction`` (world z up)."""
    forward = -direction
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    return forward, right, np.cross(right, forward)


def projected_box(points: np.ndarray, position: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """The box (left, right, bottom, top) in view coordinates (−1…1) of ``points`` seen by a camera at
    ``position`` [m] along ``direction`` (:data:`~springbalance.viz.camera.SCENE_FOV`, :data:`CAMERA_ASPECT`);
    infinite when some point lies behind the camera."""
    forward, right, up = _axes(direction)
    relative = points - position
    depth = relative @ forward
    if np.any(depth <= 0):
        return np.array([-np.inf, np.inf, -np.inf, np.inf])
    half = np.tan(np.radians(SCENE_FOV / 2))
    x, y = relative @ right / (depth * half * CAMERA_ASPECT), relative @ up / (depth * half)
    return np.array([np.min(x), np.max(x), np.min(y), np.max(y)])


def fit_view(points: np.ndarray, direction: np.ndarray, fill: float = VIEW_FILL) -> tuple[np.ndarray, np.ndarray]:
    """The target and the camera's position [m] for the line of sight ``direction`` (unit) that see every
    point within ``fill`` of the view, their projected box centred (see the module documentation).

    With the target ``t`` fixed, a point at ``(x, y)`` across the line of sight and ``z₀ = (p − t)·(−d)`` along
    it lies at depth ``D + z₀``, within the view when ``|x| ≤ fill h a (D + z₀)`` and ``|y| ≤ fill h (D + z₀)``:
    the smallest ``D`` is the largest of ``|x| / (fill h a) − z₀`` and ``|y| / (fill h) − z₀``."""
    _, right, up = _axes(direction)
    target = (points.min(axis=0) + points.max(axis=0)) / 2
    half = np.tan(np.radians(SCENE_FOV / 2))
    for _ in range(FIT_ROUNDS):
        distance = _distance(points, target, direction, fill)
        box = projected_box(points, target + distance * direction, direction)
        # the box's middle, moved to the view's centre at the target's depth
        shift = (box[0] + box[1]) / 2 * CAMERA_ASPECT * right + (box[2] + box[3]) / 2 * up
        target = target + distance * half * shift
    distance = _distance(points, target, direction, fill)
    # room left and right: move the view so that the points keep to the left, away from the pose slider's panel
    # at the bottom right (nearer points move further across the view: the largest part of the room that fits)
    room = (projected_box(points, target + distance * direction, direction)[0] + fill) * distance * half * CAMERA_ASPECT
    for part in (1.0, 0.75, 0.5, 0.25, 0.0):
        moved = target + part * room * right
        if np.max(np.abs(projected_box(points, moved + distance * direction, direction))) <= fill:
            target = moved
            break
    position = target + distance * direction
    # the same view looks at every point of its line of sight: meshcat orbits about the one nearest the middle
    middle = (points.min(axis=0) + points.max(axis=0)) / 2
    return target + ((middle - target) @ direction) * direction, position


def _distance(points: np.ndarray, target: np.ndarray, direction: np.ndarray, fill: float) -> float:
    """The smallest distance [m] from ``target`` along ``direction`` that sees every point within ``fill``."""
    forward, right, up = _axes(direction)
    half = np.tan(np.radians(SCENE_FOV / 2))
    relative = points - target
    x, y, z = relative @ right, relative @ up, relative @ forward
    needed = np.maximum(np.abs(x) / (fill * half * CAMERA_ASPECT), np.abs(y) / (fill * half)) - z
    return max(float(np.max(needed)), float(np.max(-z)) + 1e-6)  # and every point in front of the camera


def directions(points: np.ndarray) -> list[np.ndarray]:
    """The lines of sight tried for ``points`` (see the module documentation), the default's neighbours first."""
    tried = []
    for azimuth, elevation in itertools.product(np.radians(AZIMUTHS), np.radians(ELEVATIONS)):
        tried.append(
            np.array([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth), np.sin(elevation)])
        )
    _, spread, axes = np.linalg.svd(points - points.mean(axis=0), full_matrices=False)
    if spread[-1] < 0.2 * spread[-2]:  # a planar arm: within PLANE_TILT of its normal
        tried = [d for d in tried if abs(d @ axes[-1]) >= np.cos(np.radians(PLANE_TILT))] or tried
    return sorted(tried, key=lambda d: -float(d @ DEFAULT_DIRECTION))


def best_view(motion: np.ndarray, shown: np.ndarray) -> View:
    """The view that frames every point of ``motion`` (K×3 [m]: every pose of the path, :func:`view_points`)
    and shows the points of ``shown`` (the shown pose) largest (see the module documentation)."""
    best: tuple[bool, float, View] | None = None
    for direction in directions(motion):
        target, position = fit_view(motion, direction)
        box = projected_box(shown, position, direction)
        share = (float(box[1] - box[0]) / 2, float(box[3] - box[2]) / 2)
        wide, area = max(share) >= SHOWN_SIDE, share[0] * share[1]
        if best is None or (wide, area) > (best[0], best[1] * (1 + TIE)):
            best = (wide, area, View(target, position, share))
    assert best is not None  # directions() is never empty
    return best[2]
