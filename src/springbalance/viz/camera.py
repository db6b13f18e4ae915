"""Where meshcat's camera stands: far enough from the world origin that everything drawn over the whole
animation is in view.

The camera frames a sphere that holds, in every frame of the animation, the arm's links (the
bounding sphere of each visual shape), every spring with its coils, and every anchor region.
meshcat's orbit controls always look at the world origin (the arm's base, usually) and turn the
view about it, so the camera looks at the origin from just far enough that all of it lies within
90 % of the half-angle of meshcat's 75° field of view (:func:`camera_distance`). Lengths in m.
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
#: Fraction of the half field of view that the framed sphere may fill.
CAMERA_FILL = 0.9


def camera_distance(
    centres: npt.ArrayLike,
    radii: npt.ArrayLike,
    direction: npt.ArrayLike,
    fov: float = CAMERA_FOV,
    fill: float = CAMERA_FILL,
) -> float:
    """Distance [m] from the world origin along the unit vector ``direction`` of a camera that looks at
    the origin and sees every sphere (``centres`` K×3 [m], ``radii`` K [m]) within ``fill`` of the half
    field of view ``fov`` [deg]: for each sphere, the angle between the line of sight and its centre
    plus its angular radius is at most ``fill · fov / 2``. The smallest such distance, by bisection
    (beyond every sphere both angles only shrink with the distance)."""
    centres = np.atleast_2d(np.asarray(centres, dtype=float))
    radii = np.asarray(radii, dtype=float)
    direction = np.asarray(direction, dtype=float)
    half = np.radians(fill * fov / 2)

    def angle(distance: float) -> float:
        to_centres = centres - distance * direction
        reach = np.linalg.norm(to_centres, axis=1)
        sight = np.arccos(np.clip(-(to_centres @ direction) / reach, -1.0, 1.0))
        return float(np.max(sight + np.arcsin(np.minimum(radii / reach, 1.0))))

    low = float(np.max(np.linalg.norm(centres, axis=1) + radii))  # outside every sphere
    high = 2 * low / np.sin(half) + 1e-3
    for _ in range(60):
        middle = (low + high) / 2
        low, high = (middle, high) if angle(middle) > half else (low, middle)
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
    """The sphere that holds every bounding sphere (``centres`` K×3 [m], ``radii`` K [m]): its centre
    [m] and radius [m] (at least 0.15 m); and where the camera stands [m] (world) to see them all while
    it looks at the world origin: a planar arm square-on (along the normal of its plane, turned a
    little), any other from an oblique corner, at :func:`camera_distance`."""
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
    position = camera_distance(centres, radii, direction) * direction  # [m] world
    return center, radius, position


def place_camera(visualizer: Any, position: np.ndarray) -> None:
    """Put meshcat's camera at ``position`` [m] (world), looking at the world origin (its orbit target)."""
    # meshcat's orbit controls look at the world origin: the camera's parent frame must not move
    visualizer["/Cameras/default"].set_transform(np.eye(4))
    # the camera node is rotated by +90° about x (meshcat's y-up convention): world (x, y, z) = rotated (x, z, -y)
    visualizer["/Cameras/default/rotated/<object>"].set_property("position", [position[0], position[2], -position[1]])
