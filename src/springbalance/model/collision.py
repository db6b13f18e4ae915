"""The arm's collision geometry and distances to it (coal, through Pinocchio).

A spring between two points is modelled as a **capsule**: a cylinder with hemispherical ends
of radius ``r`` [m] around the straight segment between its two world end points. This module
loads the ``<collision>`` elements of the mechanism's URDF (:func:`collision_geometry`), places
them at a configuration (:class:`CollisionScene`), and measures signed distances [m] with
``coal.distance``:

- capsule to collision object (:meth:`CollisionScene.capsule_distance`), with the witness
  points and the unit normal, from which the clearance constraints of the optimisation are
  linearised (:mod:`springbalance.design.clearance`);
- point in a body's frame to that body's own collision surface (:func:`~springbalance.model.surfaces.surface_distance`),
  for anchors mounted on a link (``on: collision``).

A distance is negative when the shapes overlap (the penetration depth). For mesh geometry coal
measures to the triangles: an overlap reads 0 or a small negative depth, and a shape wholly
inside a closed mesh touching none of its triangles is not seen. ``convex=True`` replaces every
mesh by its convex hull, which has a true signed distance and a normal everywhere, and
contains the mesh, so a clearance measured to it is conservative.
"""

from __future__ import annotations

import dataclasses
import math
import weakref
from typing import TYPE_CHECKING, Sequence

import numpy as np
import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model import robots
from springbalance.model.floor import FLOOR, capsule_height, floor_contact, floor_tops, with_floor
from springbalance.model.mechanism import Mechanism
from springbalance.model.native import quiet_native_stderr

if TYPE_CHECKING:
    import coal

#: Capsule radius [m] of a spring without a helical spec sheet when none is given.
DEFAULT_RADIUS = 0.01


def capsule_radius(record: dict, radius: float | None = None) -> float:
    """Capsule radius [m] of a saved spring record (``DesignResult.springs``): half its helical spec
    sheet's outer diameter, else ``radius``, else :data:`DEFAULT_RADIUS`."""
    sheet = record.get("helical")
    if sheet and sheet.get("outer_diameter"):
        return 0.5 * float(sheet["outer_diameter"])
    return DEFAULT_RADIUS if radius is None else float(radius)


#: Each mechanism's collision geometry, loaded once (:func:`collision_geometry`); it goes with its mechanism.
_LOADED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def collision_geometry(mechanism: Mechanism) -> pin.GeometryModel:
    """The collision ``GeometryModel`` of the mechanism's URDF, loaded once per mechanism and shared (not to be
    changed): every fit and verification builds a checker (on ur5-mounted-clear, 80 loads took 1.5 s of 22.6).

    ``package://`` paths resolve against the URDF's folder, its parents and the
    example-robot-data share folder (as for the visual geometry).

    Raises:
        InputError: the mechanism has no URDF (a bare Pinocchio model), the geometry
            cannot be loaded, or the URDF has no collision geometry.
    """
    loaded = _LOADED.get(mechanism)
    if loaded is None:
        loaded = _LOADED[mechanism] = with_floor(_loaded_geometry(mechanism), mechanism.floor)
    return loaded


def _loaded_geometry(mechanism: Mechanism) -> pin.GeometryModel:
    """:func:`collision_geometry`, from the URDF."""
    source = mechanism.source
    kind = source.get("kind")
    if kind not in ("urdf", "robot", "urdf_string"):
        if mechanism.floor is not None:  # no links' geometry: the floor alone (:func:`with_floor` adds it)
            return pin.GeometryModel()
        raise InputError(
            f"mechanism {mechanism.name!r} was not loaded from a URDF (source {kind!r}); "
            "clearance and mounting need the URDF's collision geometry"
        )
    directories = robots.mesh_directories(source)
    where = repr(source["path"]) if kind in ("urdf", "robot") else "(URDF string)"
    try:
        with quiet_native_stderr():
            if kind == "urdf_string":
                geometry = pin.buildGeomFromUrdfString(
                    mechanism.model, source["text"], pin.GeometryType.COLLISION, package_dirs=directories
                )
            else:
                geometry = pin.buildGeomFromUrdf(
                    mechanism.model, source["path"], pin.GeometryType.COLLISION, package_dirs=directories
                )
    except (RuntimeError, ValueError, OSError) as error:
        raise InputError(
            f"mechanism {mechanism.name!r}: the collision geometry of {where} could not be loaded: "
            f"{' '.join(str(error).split())[:300]}"
        ) from None
    if geometry.ngeoms == 0 and mechanism.floor is None:
        raise InputError(
            f"mechanism {mechanism.name!r} has no collision geometry: the URDF {where} has no "
            "<collision> elements, so there is nothing to keep the springs clear of"
        )
    return geometry


def capsule(start: np.ndarray, end: np.ndarray, radius: float) -> tuple[coal.CollisionGeometry, coal.Transform3s]:
    """coal capsule of ``radius`` [m] around the segment ``start``–``end`` (world, [m]) and its placement: local
    z along the segment ``z = (end − start)/|end − start|``, local x the unit ``e_k × z`` for the world axis
    ``e_k`` least aligned with it, local y ``z × x``.

    A clearance check builds one per spring and pose, hundreds of thousands of times: the columns are
    computed on Python floats (``e_k × z`` has a zero and two entries of ``z``), 2.5× faster than NumPy's
    small-array operations. Each sum is written out as :func:`capsule_placements` sums it, so the two agree bit for
    bit whatever NumPy's dot does (a placement turned about the capsule's axis is the same capsule, but coal's
    distances then differ by up to 1e-7 m, enough to move a fit's path)."""
    import coal

    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    axis = end - start
    a0, a1, a2 = axis.tolist()
    length = math.sqrt((a0 * a0 + a1 * a1) + a2 * a2)
    centre = (start + end) / 2
    if length < 1e-12:
        return coal.Sphere(radius), coal.Transform3s(np.eye(3), centre)
    z0, z1, z2 = a0 / length, a1 / length, a2 / length
    m0, m1, m2 = abs(z0), abs(z1), abs(z2)
    if m0 <= m1 and m0 <= m2:  # e_x × z
        x0, x1, x2 = 0.0, -z2, z1
    elif m1 <= m2:  # e_y × z
        x0, x1, x2 = z2, 0.0, -z0
    else:  # e_z × z
        x0, x1, x2 = -z1, z0, 0.0
    norm = math.sqrt((x0 * x0 + x1 * x1) + x2 * x2)
    x0, x1, x2 = x0 / norm, x1 / norm, x2 / norm
    y0, y1, y2 = z1 * x2 - z2 * x1, z2 * x0 - z0 * x2, z0 * x1 - z1 * x0  # z × x
    rotation = np.array([[x0, y0, z0], [x1, y1, z1], [x2, y2, z2]])
    return coal.Capsule(radius, length), coal.Transform3s(rotation, centre)


def capsule_placements(starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`capsule`'s length [m], centre [m] and rotation for each of the segments ``starts``–``ends``
    (poses × 3) at once: lengths (poses), centres (poses × 3), rotations (poses × 3 × 3). The same operations,
    element by element, in the same order (a 3-vector's ``a·a`` summed ``(a₀² + a₁²) + a₂²``), so each equals
    :func:`capsule`'s bit for bit; :func:`placed_capsule` makes coal's objects of one."""
    axis = ends - starts
    length = np.sqrt((axis[:, 0] * axis[:, 0] + axis[:, 1] * axis[:, 1]) + axis[:, 2] * axis[:, 2])
    centre = (starts + ends) / 2
    with np.errstate(divide="ignore", invalid="ignore"):  # a point segment: placed_capsule makes it a sphere
        z = axis / length[:, None]
    m, zero = np.abs(z), np.zeros(len(z))
    across = np.where(
        ((m[:, 0] <= m[:, 1]) & (m[:, 0] <= m[:, 2]))[:, None],
        np.stack([zero, -z[:, 2], z[:, 1]], axis=1),  # e_x × z
        np.where(
            (m[:, 1] <= m[:, 2])[:, None],
            np.stack([z[:, 2], zero, -z[:, 0]], axis=1),  # e_y × z
            np.stack([-z[:, 1], z[:, 0], zero], axis=1),  # e_z × z
        ),
    )
    x = (
        across
        / np.sqrt((across[:, 0] * across[:, 0] + across[:, 1] * across[:, 1]) + across[:, 2] * across[:, 2])[:, None]
    )
    y = np.stack(
        [
            z[:, 1] * x[:, 2] - z[:, 2] * x[:, 1],
            z[:, 2] * x[:, 0] - z[:, 0] * x[:, 2],
            z[:, 0] * x[:, 1] - z[:, 1] * x[:, 0],
        ],
        axis=1,
    )
    return length, centre, np.stack([x, y, z], axis=2)


def placed_capsule(
    radius: float, length: float, centre: np.ndarray, rotation: np.ndarray
) -> tuple[coal.CollisionGeometry, coal.Transform3s]:
    """coal's capsule of ``radius`` [m] and placement from one of :func:`capsule_placements` (a sphere at the
    centre where the segment is a point), as :func:`capsule` builds them."""
    import coal

    if length < 1e-12:
        return coal.Sphere(radius), coal.Transform3s(np.eye(3), centre)
    return coal.Capsule(radius, float(length)), coal.Transform3s(rotation, centre)


@dataclasses.dataclass(frozen=True)
class Contact:
    """The closest approach of a capsule and one collision object.

    Attributes:
        distance: signed distance [m] (negative: penetration depth).
        index: the collision object's index in the geometry model.
        on_capsule: the capsule's witness point (world, [m]).
        on_object: the object's witness point (world, [m]).
        normal: unit vector (world) from the object towards the capsule: moving the capsule
            along it by δ raises the distance by δ.
    """

    distance: float
    index: int
    on_capsule: np.ndarray
    on_object: np.ndarray
    normal: np.ndarray


def hull(shape: coal.CollisionGeometry) -> coal.CollisionGeometry:
    """``shape`` itself, or, for a mesh (BVH), its convex hull (qhull through coal).

    coal's ``buildConvexRepresentation`` only wraps the mesh's vertices and triangles as a
    ``Convex`` without making it convex; GJK's hill-climbing support search then stalls on such a
    shape and reports wrong distances (seen: +0.33 m where the mesh overlaps). ``buildConvexHull``
    builds the real hull.
    """
    import coal

    if isinstance(shape, coal.BVHModelBase):
        if shape.convex is None:
            shape.buildConvexHull(True, "Qt")
        return shape.convex
    return shape


def _convex(geometry: pin.GeometryModel) -> pin.GeometryModel:
    """A copy of ``geometry`` in which every mesh (BVH) is replaced by its convex hull."""
    hulls = pin.GeometryModel()
    for obj in geometry.geometryObjects:
        obj = obj.copy()
        obj.geometry = hull(obj.geometry)
        hulls.addGeometryObject(obj)
    return hulls


class CollisionScene:
    """The arm's collision objects placed at one configuration at a time.

    Args:
        mechanism: the arm.
        geometry: its collision geometry (default: :func:`collision_geometry`).
        convex: replace meshes by their convex hulls (see the module documentation).
    """

    def __init__(self, mechanism: Mechanism, geometry: pin.GeometryModel | None = None, convex: bool = False):
        import coal

        self.mechanism = mechanism
        geometry = collision_geometry(mechanism) if geometry is None else geometry
        self._source = geometry  # the hulls may share memory with the meshes they were built from: keep them
        self.geometry = _convex(geometry) if convex else geometry
        self.objects = list(self.geometry.geometryObjects)
        model = mechanism.model
        #: the body (URDF link, or the ground for the floor) that carries each collision object
        self.bodies = [model.frames[obj.parentFrame].name for obj in self.objects]
        #: what reports call each object's link: its body, or :data:`FLOOR` for the floor
        self.links = [FLOOR if obj.name == FLOOR else body for obj, body in zip(self.objects, self.bodies)]
        self._floors = floor_tops(self.objects)  # (measured in closed form: floor.py)
        self._data, self._geometry_data = model.createData(), self.geometry.createData()
        self._request = coal.DistanceRequest()
        self._request.enable_signed_distance = True
        self._placements: list = []
        self._bounds: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # bounding_capsules, once

    def indices_except(self, bodies: Sequence[str]) -> list[int]:
        """Indices of the collision objects not carried by any of ``bodies``; the floor is left out too when one of
        ``bodies`` is the ground or a link welded to it (a spring anchored on the arm's base stands on the floor)."""
        grounded = any(self.mechanism.is_ground(body) for body in bodies)
        return [i for i, body in enumerate(self.bodies) if body not in bodies and not (grounded and i in self._floors)]

    def place(self, configuration: np.ndarray) -> None:
        """Move the arm and its collision objects to configuration ``q`` (Pinocchio's order)."""
        self.move(configuration)
        self._placements = [None] * len(self.objects)  # coal's, built when an object is first asked for

    def _placement(self, index: int) -> coal.Transform3s:
        """coal's placement of object ``index`` at the placed configuration."""
        import coal

        placement = self._placements[index]
        if placement is None:
            oMg = self._geometry_data.oMg[index]
            placement = self._placements[index] = coal.Transform3s(np.array(oMg.rotation), np.array(oMg.translation))
        return placement

    def move(self, configuration: np.ndarray) -> None:
        """Move the arm's frames and objects' placements to ``q`` without building coal's placements: for
        :meth:`frame` and :meth:`object_placements` alone (:meth:`distance_to` needs :meth:`place`)."""
        model = self.mechanism.model
        pin.forwardKinematics(model, self._data, configuration)
        pin.updateFramePlacements(model, self._data)
        pin.updateGeometryPlacements(model, self._data, self.geometry, self._geometry_data)

    def object_placements(self) -> tuple[np.ndarray, np.ndarray]:
        """World rotations (n×3×3) and translations (n×3) [m] of the objects at the current configuration."""
        placements = self._geometry_data.oMg
        return np.array([p.rotation for p in placements]), np.array([p.translation for p in placements])

    def bounding_capsules(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per object, a capsule that holds it, in the object's own frame: ``(start, end, radius)`` (n×3, n×3, n)
        [m]. Its axis runs along the longest side of the object's bounding box through the box's centre, as long
        as that side; its radius is the half-diagonal of the box's cross-section (a point of the box projects onto
        the axis within the side and lies within that distance of it)."""
        if self._bounds is None:
            starts, ends, radii = [], [], []
            for obj in self.objects:
                shape = obj.geometry
                shape.computeLocalAABB()
                lower, upper = np.array(shape.aabb_local.min_), np.array(shape.aabb_local.max_)
                centre, half = (lower + upper) / 2, (upper - lower) / 2
                axis = int(np.argmax(half))
                step = np.zeros(3)
                step[axis] = half[axis]
                starts.append(centre - step)
                ends.append(centre + step)
                radii.append(float(np.linalg.norm(np.delete(half, axis))))
            self._bounds = (np.array(starts), np.array(ends), np.array(radii))
        return self._bounds

    def frame(self, frame_id: int) -> pin.SE3:
        """World placement of a frame at the current configuration."""
        return self._data.oMf[frame_id]

    def distance_to(self, shape: coal.CollisionGeometry, placement: coal.Transform3s, index: int) -> float:
        """Signed distance [m] from ``shape`` placed at ``placement`` (world) to object ``index``; with a
        :func:`capsule`, the distance of :meth:`capsule_distance` without its witness points, for a capsule
        checked against many objects (built once)."""
        import coal

        if index in self._floors and isinstance(shape, coal.Capsule):
            return capsule_height(shape, placement, self._floors[index])
        return float(
            coal.distance(
                shape,
                placement,
                self.objects[index].geometry,
                self._placement(index),
                self._request,
                coal.DistanceResult(),
            )
        )

    def between(self, first: int, second: int) -> float:
        """Signed distance [m] between objects ``first`` and ``second`` at the placed configuration."""
        return self.distance_to(self.objects[first].geometry, self._placement(first), second)

    def capsule_distance(self, start: np.ndarray, end: np.ndarray, radius: float, index: int) -> Contact:
        """Signed distance from the capsule ``start``–``end`` of ``radius`` [m] (world) to object ``index``."""
        import coal

        if index in self._floors:
            return Contact(
                *floor_contact(np.asarray(start, float), np.asarray(end, float), radius, self._floors[index], index)
            )
        shape, placement = capsule(start, end, radius)
        result = coal.DistanceResult()
        distance = coal.distance(
            shape, placement, self.objects[index].geometry, self._placement(index), self._request, result
        )
        return Contact(
            float(distance),
            index,
            np.array(result.getNearestPoint1()),
            np.array(result.getNearestPoint2()),
            -np.array(result.normal),
        )


def segment_distances(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Distances [m] between the segments ``p1``–``q1`` and ``p2``–``q2`` (arrays of points, ...×3, broadcast):
    the closest points' parameters ``s, t ∈ [0, 1]`` clamped as in Ericson, *Real-Time Collision Detection*
    (2005), §5.1.9, for every pair at once. A segment of zero length is a point."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e = np.einsum("...i,...i", d1, d1), np.einsum("...i,...i", d2, d2)
    b, c, f = np.einsum("...i,...i", d1, d2), np.einsum("...i,...i", d1, r), np.einsum("...i,...i", d2, r)
    tiny = 1e-18
    safe_a, safe_e = np.where(a > tiny, a, 1.0), np.where(e > tiny, e, 1.0)
    denominator = a * e - b * b
    s = np.where(
        denominator > tiny, np.clip((b * f - c * e) / np.where(denominator > tiny, denominator, 1.0), 0, 1), 0.0
    )
    t = (b * s + f) / safe_e
    s = np.where(t < 0, np.clip(-c / safe_a, 0, 1), np.where(t > 1, np.clip((b - c) / safe_a, 0, 1), s))
    t = np.clip(t, 0, 1)
    # a point: the other segment's parameter alone
    s = np.where(a > tiny, s, 0.0)
    t = np.where(e > tiny, np.where(a > tiny, t, np.clip(f / safe_e, 0, 1)), 0.0)
    s = np.where((e <= tiny) & (a > tiny), np.clip(-c / safe_a, 0, 1), s)
    return np.linalg.norm(p1 + s[..., None] * d1 - p2 - t[..., None] * d2, axis=-1)


def capsule_contact(
    start_1: np.ndarray, end_1: np.ndarray, radius_1: float, start_2: np.ndarray, end_2: np.ndarray, radius_2: float
) -> Contact:
    """Signed distance between two capsules (world, [m]); ``normal`` points from capsule 2 to capsule 1,
    ``on_capsule`` lies on capsule 1 and ``on_object`` on capsule 2 (``index`` is -1)."""
    import coal

    request = coal.DistanceRequest()
    request.enable_signed_distance = True
    result = coal.DistanceResult()
    shape_1, placement_1 = capsule(start_1, end_1, radius_1)
    shape_2, placement_2 = capsule(start_2, end_2, radius_2)
    distance = coal.distance(shape_1, placement_1, shape_2, placement_2, request, result)
    normal = -np.array(result.normal)
    if not np.linalg.norm(normal) > 0.5:
        # coincident axes have no witness direction: take the world axis least aligned with capsule 1,
        # made perpendicular to it, (or, for a point, the midpoints' difference, else +z)
        axis = np.asarray(end_1, dtype=float) - np.asarray(start_1, dtype=float)
        if np.linalg.norm(axis) > 1e-12:
            axis /= np.linalg.norm(axis)
            normal = np.eye(3)[int(np.argmin(np.abs(axis)))]
            normal = normal - (normal @ axis) * axis
        else:
            normal = np.array([0.0, 0.0, 1.0])
        normal /= np.linalg.norm(normal)
    return Contact(
        float(distance), -1, np.array(result.getNearestPoint1()), np.array(result.getNearestPoint2()), normal
    )
