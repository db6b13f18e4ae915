"""Where meshcat's camera stands and what it looks at: the arm's bounding box over the whole animation,
from a three-quarter view, close enough that the arm and its springs fill most of the view.

The camera frames the box that holds, in every frame of the animation, the arm's links (the bounding
sphere of each visual shape) and every spring with its coils (the anchor regions, hidden by default,
are not framed). meshcat's orbit controls always look at the origin of the scene and turn the view
about it, so the scene is moved (the ``/meshcat`` node) by minus the box's centre: the camera looks at
the centre of the arm, and orbiting turns the arm about its own middle. It stands on a three-quarter
line of sight (a planar arm: along the normal of its plane, turned a little; any other from an oblique
corner above), just far enough that everything lies within 90 % of the half-angle of meshcat's 75°
field of view vertically and of its width for a view :data:`CAMERA_ASPECT` wide
(:func:`camera_distance`). The floor grid is moved under the arm (to the box's lowest
point) and scaled to the arm's size. Lengths in m.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from springbalance.viz.regions import RegionShape, region_points
from springbalance.viz.tracks import SpringTrack

#: Field of view (vertical) of meshcat's default camera [deg].
CAMERA_FOV = 75.0
#: Field of view (vertical) [deg] the scene gives meshcat's camera (:func:`place_camera`): narrower than meshcat's
#: default, from farther away, so that what is near the camera is not drawn much larger than what is far.
SCENE_FOV = 45.0
#: Fraction of the half field of view that the framed sphere may fill.
CAMERA_FILL = 0.9


#: Width over height of the view the camera is placed for (a browser window; the tests' is 900×700).
CAMERA_ASPECT = 1.3


def camera_distance(
    centres: npt.ArrayLike,
    radii: npt.ArrayLike,
    direction: npt.ArrayLike,
    fov: float = CAMERA_FOV,
    fill: float = CAMERA_FILL,
    aspect: float | None = None,
) -> float:
    """Distance [m] from the world origin along the unit vector ``direction`` of a camera that looks at
    the origin and sees every sphere (``centres`` K×3 [m], ``radii`` K [m]) within ``fill`` of the half
    field of view ``fov`` [deg] (vertical). Without ``aspect``: for each sphere, the angle between the
    line of sight and its centre plus its angular radius is at most ``fill · fov / 2`` (a cone). With
    ``aspect`` (width over height of the view): the same separately in the camera's vertical plane
    (half-angle ``fill · fov / 2``) and in its horizontal plane (half-angle ``fill · atan(aspect ·
    tan(fov / 2))``), the view's rectangle with world z up. The smallest such distance, by bisection
    (beyond every sphere the angles only shrink with the distance)."""
    centres = np.atleast_2d(np.asarray(centres, dtype=float))
    radii = np.asarray(radii, dtype=float)
    direction = np.asarray(direction, dtype=float)
    half = np.radians(fill * fov / 2)
    forward = -direction
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right = right / np.linalg.norm(right) if np.linalg.norm(right) > 1e-9 else np.array([1.0, 0.0, 0.0])
    up = np.cross(right, forward)
    wide = fill * np.arctan(aspect * np.tan(np.radians(fov / 2))) if aspect else half

    def planar(depth: np.ndarray, side: np.ndarray) -> np.ndarray:
        """Angle from the line of sight to each sphere's far edge in one plane of the camera."""
        reach = np.hypot(depth, side)
        return np.arctan2(np.abs(side), depth) + np.arcsin(np.minimum(radii / reach, 1.0))

    def beyond(distance: float) -> bool:
        to_centres = centres - distance * direction
        if aspect is None:
            reach = np.linalg.norm(to_centres, axis=1)
            sight = np.arccos(np.clip(-(to_centres @ direction) / reach, -1.0, 1.0))
            return bool(np.max(sight + np.arcsin(np.minimum(radii / reach, 1.0))) > half)
        depth = to_centres @ forward
        return bool(np.max(planar(depth, to_centres @ up)) > half or np.max(planar(depth, to_centres @ right)) > wide)

    low = float(np.max(np.linalg.norm(centres, axis=1) + radii))  # outside every sphere
    high = 2 * low / np.sin(half) + 1e-3
    for _ in range(60):
        middle = (low + high) / 2
        low, high = (middle, high) if beyond(middle) else (low, middle)
    return high


def bounding_spheres(
    springs: list[SpringTrack],
    regions: list[RegionShape],
    model: pin.Model,
    visual_model: pin.GeometryModel,
    configurations: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Centres (K×3) [m] and radii (K) [m] of spheres that hold, over every pose of ``configurations``
    (N×nq), what is drawn:

    - each spring's two ends, with its coil radius plus its wire radius (so the coils are held);
    - the corners of each anchor region on its body;
    - each joint's and frame's origin of ``model``, and the bounding sphere of each shape of
      ``visual_model`` (the arm's links).
    """
    centres, radii = [], []
    for spring in springs:
        reach = spring.coil_radius + spring.wire_radius
        for points in (spring.starts, spring.ends, *spring.points_by_end().values()):
            centres.append(points)
            radii.append(np.full(len(points), reach))
    for region in regions:
        corners = region_points(region)
        world = np.einsum("nij,kj->nki", region.placements[:, :3, :3], corners) + region.placements[:, None, :3, 3]
        centres.append(world.reshape(-1, 3))
        radii.append(np.zeros(world.shape[0] * world.shape[1]))
    _add_arm_spheres(centres, radii, model, visual_model, configurations)
    return np.vstack(centres), np.concatenate(radii)


def _add_arm_spheres(
    centres: list, radii: list, model: pin.Model, visual_model: pin.GeometryModel, configurations: np.ndarray
) -> None:
    """Append, per pose, the joints' and frames' origins and the visual shapes' bounding spheres."""
    data, visual_data = model.createData(), visual_model.createData()
    shapes = []  # (local centre, radius) of each visual shape's bounding sphere
    for geometry in visual_model.geometryObjects:
        try:
            geometry.geometry.computeLocalAABB()
            shapes.append((np.array(geometry.geometry.aabb_center), float(geometry.geometry.aabb_radius)))
        except (AttributeError, RuntimeError):
            shapes.append((np.zeros(3), 0.0))
    for q in configurations:
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        pin.updateGeometryPlacements(model, data, visual_model, visual_data)
        centres.append(np.array([data.oMi[j].translation for j in range(model.njoints)]))
        centres.append(np.array([data.oMf[f].translation for f in range(model.nframes)]))
        radii += [np.zeros(model.njoints), np.zeros(model.nframes)]
        if shapes:
            centres.append(np.array([visual_data.oMg[i].act(centre) for i, (centre, _) in enumerate(shapes)]))
            radii.append(np.array([radius for _, radius in shapes]))


def camera_view(centres: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """The box that holds every bounding sphere (``centres`` K×3 [m], ``radii`` K [m]): its centre [m]
    (the camera's target), the radius [m] of the sphere about that centre that holds them all (at least
    0.15 m); and where the camera stands [m] (world) to see them all while it looks at the centre: a
    planar arm square-on (along the normal of its plane, turned a little), any other from an oblique
    corner above, at :func:`camera_distance` from the centre."""
    lower, upper = (centres - radii[:, None]).min(axis=0), (centres + radii[:, None]).max(axis=0)
    center = (lower + upper) / 2
    radius = max(float(np.max(np.linalg.norm(centres - center, axis=1) + radii)), 0.15)  # [m]
    # a planar arm is seen square-on (along the normal of its plane), any other from an oblique corner
    _, spread, axes = np.linalg.svd(centres - centres.mean(axis=0), full_matrices=False)
    if spread[-1] < 0.2 * spread[-2]:
        normal = axes[-1] if axes[-1] @ np.array([0.3, -1.0, 0.0]) >= 0 else -axes[-1]
        direction = normal + np.array([0.35, -0.25, 0.45])
    else:
        direction = np.array([1.0, -1.3, 0.8])
    direction /= np.linalg.norm(direction)
    position = center + camera_distance(centres - center, radii, direction, aspect=CAMERA_ASPECT) * direction
    return center, radius, position


def floor_height(centres: np.ndarray, radii: np.ndarray) -> float:
    """Height [m] (world z) of the lowest point of the spheres (``centres`` K×3 [m], ``radii`` K [m]):
    where the floor grid goes, under the arm."""
    return float(np.min(centres[:, 2] - radii))


#: meshcat's floor grid: 20 m wide (40 cells of 0.5 m); it is scaled to this many times the framed radius
GRID_SPAN = 4.0


def place_camera(
    visualizer: Any,
    position: np.ndarray,
    target: np.ndarray | None = None,
    floor: float | None = None,
    radius: float | None = None,
) -> None:
    """Put meshcat's camera at ``position`` [m] (world), looking at ``target`` [m] (world; default the
    origin), with a field of view of :data:`SCENE_FOV`: the scene (``/meshcat``) is moved by ``-target``, since meshcat's orbit controls look at
    the scene's origin. With ``floor`` [m] the grid goes to that height under the arm, and with
    ``radius`` [m] (the framed sphere's) it spans :data:`GRID_SPAN` times it."""
    target = np.zeros(3) if target is None else np.asarray(target, dtype=float)
    shift = np.eye(4)
    shift[:3, 3] = -target
    visualizer["/meshcat"].set_transform(shift)
    if floor is not None:
        grid = np.eye(4)
        if radius is not None:
            grid[:3, :3] *= GRID_SPAN * radius / 20.0  # meshcat's grid is 20 m wide
        grid[:3, 3] = [0.0, 0.0, floor - target[2]]
        visualizer["/Grid"].set_transform(grid)
    # meshcat's orbit controls look at the origin: the camera's parent frame must not move
    visualizer["/Cameras/default"].set_transform(np.eye(4))
    local = np.asarray(position, dtype=float) - target
    # the camera node is rotated by +90° about x (meshcat's y-up convention): world (x, y, z) = rotated (x, z, -y)
    visualizer["/Cameras/default/rotated/<object>"].set_property("position", [local[0], local[2], -local[1]])
    visualizer["/Cameras/default/rotated/<object>"].set_property("fov", SCENE_FOV)  # three.js applies it per render
