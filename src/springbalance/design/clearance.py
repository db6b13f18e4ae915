r"""Springs that fit the arm: clearance from its links, and anchors mounted on its surfaces.

**Clearance.** A two-point spring is a capsule of radius ``r`` [m] (half the outer diameter of
its coil, or :attr:`Clearance.radius`) around the segment between its world end points
``E_a(x), E_b(x)``; it must keep ``margin`` from every collision object of the arm except those
of its own two anchor bodies, at every pose (:mod:`springbalance.model.collision`). Meshes count
as their convex hulls, which contain them.

For a fixed pose the ends are affine in the anchor coordinates (docs/model.md §2), and the
distance to a convex object is linearised by a **separating plane**: coal gives the witness
point ``w`` on the object and the unit normal ``n`` towards the capsule, and both ends must stay
on the far side of the plane through ``w``,

.. math:: n^\top (E_e(x) - w) - r - m^+ \ge 0, \qquad e \in \{a, b\},

two rows affine in ``x`` (:class:`~springbalance.design.problem.LinearRows`). Keeping both ends
beyond the plane keeps the whole segment beyond it, so the rows are *sufficient* for the margin at
that pose, and at the design where they are built they hold exactly when the distance is at
least ``m^+`` (the closest point of the segment has the smallest ``n``-coordinate). ``m^+`` is
the margin plus a buffer (:attr:`Clearance.buffer`) for the poses between the ones checked.

Two springs (``between_springs``) are kept apart by the plane halfway between their witness
points: each end of one spring on its side by ``r_i + m^+/2``.

**The loop** (:func:`fit_to_arm`): from the multi-start's optimum, check every spring against
every object at ``check_samples`` poses (scrambled Sobol, seed 0, over the workspace's joint
ranges). Each pose where a spring comes closer than the margin joins the watched set; the rows
of every watched pose are rebuilt at the current design and the problem is solved again from
it (one warm start). When the check set is clear, a 4× denser set (seed 1) is checked too, and
its violations join the watched set. When both are clear, a bounded descent over the joint
coordinates from the closest sampled poses of every pair that comes near searches for the
closest approach between the samples (in six joints, even thousands of samples lie far apart),
and the minima below the margin join the watched set and are checked in every later round.
The loop ends when all three are clear, or after
:attr:`Clearance.rounds` rounds; its record (:class:`FitRecord`) says which, and what the
clearance cost (the objective before and after).

**Mounting.** An anchor ``on: collision`` lies ``offset`` [m] outside its body's collision
surface (the union of the body's objects; meshes as hulls). In the body frame this does not
depend on the pose: with ``w`` the closest surface point and ``n`` the outward normal at the
current anchor point ``p``, the row ``n^\top (p(x) - w) - \text{offset} + t \ge 0`` (``t`` = 0.2 mm)
holds it on the far side of the offset tangent plane, and ``\text{offset} - n^\top (p(x) - w) + t \ge 0``,
kept for every tangent plane met so far, inside the (convex) offset body: each such plane bounds
that body, so none cuts off a point of its surface. Together they hold the anchor on the surface;
they are rebuilt every round until ``p`` is within 0.5 mm of it. Floor and wall mountings need no loop: they are plane regions
(:class:`~springbalance.springs.params.Anchor`).
"""

from __future__ import annotations

import copy
import dataclasses
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from springbalance.design.solvers import Solution, solve_problem
from springbalance.errors import InputError, SolverError
from springbalance.model.collision import (DEFAULT_RADIUS, CollisionScene, Contact, capsule_contact, collision_geometry,
                                           surface_distance, body_objects, hull)
from springbalance.model.workspace import Workspace
from springbalance.springs.params import Free

if TYPE_CHECKING:
    from springbalance.design.problem import DesignProblem

#: Half-width [m] of the band the mounting rows keep an anchor in around its offset surface.
MOUNT_TOLERANCE = 2e-4
#: An anchor counts as on its surface when within this distance [m] of it.
MOUNT_ACCEPT = 5e-4
#: Most poses per spring and object (and round) that join the watched set.
WORST_PER_PAIR = 4
#: Closest sampled poses per spring and object (a quarter of the joint box apart) from which
#: :meth:`_Checker.descend` searches.
DESCENTS_PER_PAIR = 2
#: A pair is searched when its closest sampled pose is within this distance [m] of the margin.
DESCENT_BAND = 0.02
#: Most distance evaluations of one descent.
DESCENT_EVALUATIONS = 150


@dataclasses.dataclass(frozen=True)
class Clearance:
    """What clearance the springs must keep from the arm (see the module documentation).

    Attributes:
        margin: smallest distance [m] between a spring's capsule and any link it is not attached to.
        check_samples: poses checked by the loop (a 4× denser set is checked at the end).
        radius: capsule radius [m] of springs without a helical spec sheet (default 0.01 m).
        between_springs: keep the springs ``margin`` from each other too.
        buffer: extra distance [m] the rows ask for, for the poses between the checked ones
            (default: 10 % of the margin, at least 0.5 mm).
        rounds: most re-solves of the loop.
        starts: how many of the multi-start's best feasible designs the loop fits (each from its own
            start); the fitted design of lowest objective is kept. The loop linearises around the
            design it starts from, so a second or third start can end in a better optimum.
    """

    margin: float = 0.005
    check_samples: int = 1024
    radius: float | None = None
    between_springs: bool = False
    buffer: float | None = None
    rounds: int = 12
    starts: int = 1

    def __post_init__(self) -> None:
        for key in ("margin", "buffer"):
            value = getattr(self, key)
            if value is None and key == "buffer":
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value < 0:
                raise InputError(f"clearance.{key} must be a finite number ≥ 0 [m], got {value!r}")
        if self.radius is not None and (isinstance(self.radius, bool) or not isinstance(self.radius, (int, float))
                                        or not np.isfinite(self.radius) or self.radius <= 0):
            raise InputError(f"clearance.radius must be a finite number > 0 [m], got {self.radius!r}")
        for key in ("check_samples", "rounds", "starts"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise InputError(f"clearance.{key} must be an integer ≥ 1, got {value!r}")

    @property
    def target(self) -> float:
        """The distance [m] the rows ask for: margin + buffer."""
        buffer = max(0.1 * self.margin, 5e-4) if self.buffer is None else self.buffer
        return self.margin + buffer

    def to_dict(self) -> dict[str, Any]:
        return {key: value for key, value in dataclasses.asdict(self).items() if value is not None}

    @classmethod
    def from_dict(cls, record: Any, where: str = "clearance") -> "Clearance":
        if not isinstance(record, dict):
            raise InputError(f"{where}: expected a mapping {{margin, check_samples, ...}}, got {record!r}")
        valid = [field.name for field in dataclasses.fields(cls)]
        unknown = [key for key in record if key not in valid]
        if unknown:
            raise InputError(f"{where}: unknown key {unknown[0]!r}; valid keys: {', '.join(valid)}")
        return cls(**record)


@dataclasses.dataclass
class FitRecord:
    """What fitting the springs to the arm did and cost.

    Attributes:
        rounds: re-solves made.
        rows: linearised rows in the last solve.
        converged: the last check found no spring below the margin and every mounted anchor on its
            surface.
        objective_before: the objective of the multi-start's optimum (no clearance, no mounting).
        objective: the objective of the fitted design.
        closest: spring name → smallest distance [m] to the arm (or another spring) over the
            poses checked in the last round (check set and dense set).
        mounts: ``"<spring>.<end>"`` → distance [m] of a mounted anchor from its offset surface.
        poses: the number of poses checked (check set + dense set).
        seconds: wall time of the loop (of every fitted start).
        starts: how many of the multi-start's designs were fitted (the best fit is this record's).
    """

    rounds: int
    rows: int
    converged: bool
    objective_before: float
    objective: float
    closest: dict = dataclasses.field(default_factory=dict)
    mounts: dict = dataclasses.field(default_factory=dict)
    poses: int = 0
    seconds: float = 0.0
    starts: int = 1

    @property
    def cost_percent(self) -> float:
        """How much worse the objective got [%]."""
        if self.objective_before <= 0:
            return 0.0
        return 100.0 * (self.objective - self.objective_before) / self.objective_before

    def to_dict(self) -> dict[str, Any]:
        return {**dataclasses.asdict(self), "cost_percent": self.cost_percent}

    @classmethod
    def from_dict(cls, record: Any) -> "FitRecord | None":
        """The record a saved design carries (None when it has none or it is damaged)."""
        if not isinstance(record, dict):
            return None
        try:
            return cls(**{field.name: record[field.name] for field in dataclasses.fields(cls) if field.name in record})
        except TypeError:
            return None


@dataclasses.dataclass
class LinearRows:
    """Constraint rows affine in the design variables, ``G x + h ≥ 0`` [m], over named variables.

    The clearance and mounting constraints (:mod:`springbalance.design.clearance`) are such rows,
    linearised at the current design. They are kept by variable *name*, so that a problem with
    some other variables fixed (:meth:`DesignProblem.with_springs`) takes them over.

    Attributes:
        names: the design variables the rows depend on.
        matrix: ``G`` (rows × names) [m per unit of each variable].
        offset: ``h`` (rows) [m].
        labels: what each row keeps (e.g. ``"s1 clear of link2 at pose 17"``).
        scale: a typical size of a violation [m], for the solvers' scaling.
    """

    names: list
    matrix: np.ndarray
    offset: np.ndarray
    labels: list
    scale: float = 0.001

    def __len__(self) -> int:
        return int(self.offset.size)


# ====================================================================== mounting
def mounted_anchors(springs) -> list[tuple[Any, str, Any]]:
    """``(spring, end, anchor)`` of every anchor mounted ``on: collision``."""
    return [(spring, end, anchor) for spring in springs for end, anchor in spring.anchors.items()
            if getattr(anchor, "mount", None) == "collision"]


def resolve_mounts(mechanism, springs: list) -> list:
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
            setattr(spring, end, anchor)     # two-point springs keep their ends as attributes a and b
        resolved.append(spring)
    return resolved


def body_bounds(mechanism, geometry, body: str) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounds (body frame, [m]) of ``body``'s collision objects."""
    import coal

    objects = body_objects(mechanism, geometry, body)
    if not objects:
        raise InputError(f"body {body!r} has no collision geometry in the URDF, so an anchor cannot be mounted "
                         "on it with 'on: collision'; give a box, point, segment or plane instead")
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


def check_mounts(problem: DesignProblem) -> list[tuple[Any, str, Any]]:
    """Check that every ``on: collision`` anchor's box reaches its offset surface; return the mounted anchors.

    Raises:
        InputError: the body has no collision geometry, or no point of the box lies ``offset``
            from the body's collision surface (names the spring, end, body and the distances found).
    """
    mounts = mounted_anchors(problem.springs)
    if not mounts:
        return []
    geometry = collision_geometry(problem.mechanism)
    for spring, end, anchor in mounts:
        region = anchor.region()
        grid = np.linspace(0.0, 1.0, 7)
        axes = np.meshgrid(*[region.lower[i] + (region.upper[i] - region.lower[i]) * grid
                             for i in range(region.basis.shape[1])], indexing="ij")
        coordinates = np.stack([axis.reshape(-1) for axis in axes], axis=1) if axes else np.zeros((1, 0))
        distances = np.array([surface_distance(problem.mechanism, geometry, anchor.body, region.point(c))[0]
                              for c in coordinates]) - anchor.offset
        if distances.min() > MOUNT_ACCEPT or distances.max() < -MOUNT_ACCEPT:
            raise InputError(
                f"spring {spring.name!r} end {end}: no point of its box on {anchor.body!r} lies {anchor.offset * 1e3:g} mm "
                f"from the body's collision surface (the box is {distances.min() * 1e3 + anchor.offset * 1e3:.1f} to "
                f"{distances.max() * 1e3 + anchor.offset * 1e3:.1f} mm from it): no anchor can reach the mounting surface")
    return mounts


def mount_planes(problem: DesignProblem, x: np.ndarray, planes: dict | None = None) -> dict:
    """Per mounted anchor (``(spring name, end, scenario)``), its tangent planes ``(w, n)``: those in ``planes``
    and the one at design ``x`` (body frame: closest surface point ``w`` [m], outward unit normal ``n``)."""
    planes = {key: list(value) for key, value in (planes or {}).items()}
    if not problem.mounts:
        return planes
    geometry = collision_geometry(problem.mechanism)
    for spring, end, anchor in problem.mounts:
        for scenario in range(problem.model.n_scenarios):
            P = problem.model.anchor_point(spring, end, x, scenario)
            distance, w, normal = surface_distance(problem.mechanism, geometry, anchor.body, P)
            if distance > 1e-9:
                normal = (P - w) / np.linalg.norm(P - w)
            history = planes.setdefault((spring.name, end, scenario), [])
            if not any(np.allclose(w, old_w) and np.allclose(normal, old_n) for old_w, old_n in history):
                history.append((w, normal))
            else:   # the current plane moves to the end (it is the one the anchor must lie on)
                history.append(history.pop(next(i for i, (old_w, old_n) in enumerate(history)
                                                 if np.allclose(w, old_w) and np.allclose(normal, old_n))))
    return planes


def mount_rows(problem: DesignProblem, x: np.ndarray) -> LinearRows | None:
    """The rows that hold every ``on: collision`` anchor on its offset surface, linearised at ``x``."""
    return _rows(problem, x, [], [], mount_planes(problem, x))


def _mount_errors(problem: DesignProblem, x: np.ndarray, geometry) -> dict[str, float]:
    """``"<spring>.<end>"`` → distance [m] of each mounted anchor from its offset surface at ``x``."""
    errors = {}
    for spring, end, anchor in problem.mounts:
        for scenario in range(problem.model.n_scenarios):
            point = problem.model.anchor_point(spring, end, x, scenario)
            distance = surface_distance(problem.mechanism, geometry, anchor.body, point)[0]
            key = f"{spring.name}.{end}"
            errors[key] = max(errors.get(key, 0.0), abs(distance - anchor.offset))
    return errors


# ====================================================================== rows
class _AnchorMaps:
    """Per (spring, end, scenario): the anchor point ``P(x) = P0 + J (x - x0)`` (body frame), exact since affine."""

    def __init__(self, problem: DesignProblem):
        self.problem = problem
        self._jacobians: dict = {}

    def jacobian(self, spring, end: str, scenario: int) -> np.ndarray:
        key = (spring.name, end, scenario)
        if key not in self._jacobians:
            model = self.problem.model
            n = self.problem.variables.size
            zero = np.zeros(n)
            base = model.anchor_point(spring, end, zero, scenario)
            self._jacobians[key] = np.column_stack(
                [model.anchor_point(spring, end, np.eye(n)[k], scenario) - base for k in range(n)]) if n else np.zeros((3, 0))
        return self._jacobians[key]


def _rows(problem: DesignProblem, x: np.ndarray, object_cuts: list, spring_cuts: list,
          planes: dict) -> LinearRows | None:
    """Linear rows at design ``x``: mounting rows, then the given cuts.

    ``planes``: per mounted anchor, its tangent planes of the offset surface (:func:`mount_planes`).
    The anchor stays inside every one of them, ``n·(p - w) ≤ offset``: each bounds the convex
    offset body, so none cuts off a point of its surface, and together they keep the anchor on
    the part of the surface they have seen. It lies on the last one: ``n·(p - w) ≥ offset``.

    ``object_cuts``: ``(label, spring, scenario, frames (R_a, p_a, R_b, p_b), contact, radius, target)``;
    ``spring_cuts``: ``(label, (spring_i, frames_i, r_i), (spring_j, frames_j, r_j), scenario, contact, target)``.
    """
    maps = _AnchorMaps(problem)
    model = problem.model
    n = problem.variables.size
    matrix, offset, labels = [], [], []

    def end_row(spring, end, scenario, rotation, translation, normal, point):
        """Gradient and value of ``n·(R P(x) + p - w)`` at ``x``."""
        P = model.anchor_point(spring, end, x, scenario)
        gradient = normal @ rotation @ maps.jacobian(spring, end, scenario)
        value = float(normal @ (rotation @ P + translation - point))
        return gradient, value

    identity, zero = np.eye(3), np.zeros(3)
    for spring, end, anchor in problem.mounts:
        for scenario in range(model.n_scenarios):
            history = planes[(spring.name, end, scenario)]
            for index, (w, normal) in enumerate(history):
                gradient, value = end_row(spring, end, scenario, identity, zero, normal, w)
                for sign in ((-1.0, 1.0) if index == len(history) - 1 else (-1.0,)):
                    matrix.append(sign * gradient)
                    offset.append(sign * (value - anchor.offset) + MOUNT_TOLERANCE - sign * gradient @ x)
                    labels.append(f"{spring.name}.{end} {'on' if sign > 0 else 'within'} the offset surface "
                                  f"of {anchor.body}")
    for label, spring, scenario, frames, contact, radius, target in object_cuts:
        for end, (rotation, translation) in zip(_ends_of(spring), frames):
            gradient, value = end_row(spring, end, scenario, rotation, translation, contact.normal, contact.on_object)
            matrix.append(gradient)
            offset.append(value - radius - target - gradient @ x)
            labels.append(f"{label}, end {end}")
    for label, first, second, scenario, contact, target in spring_cuts:
        middle = (contact.on_capsule + contact.on_object) / 2
        for (spring, frames, radius), sign in ((first, 1.0), (second, -1.0)):
            for end, (rotation, translation) in zip(_ends_of(spring), frames):
                gradient, value = end_row(spring, end, scenario, rotation, translation, sign * contact.normal, middle)
                matrix.append(gradient)
                offset.append(value - radius - target / 2 - gradient @ x)
                labels.append(f"{label}, {spring.name} end {end}")
    if not offset:
        return None
    return LinearRows(list(problem.variables.names), np.array(matrix).reshape(-1, n), np.array(offset), labels)


# ====================================================================== the loop
def _ends_of(spring) -> tuple[str, str]:
    """The ends of a spring's own body: ``a`` and ``b``, or for a routed spring ``a`` and its first
    pulley (the capsule is its first segment; its cable beyond is not checked)."""
    return getattr(spring, "spring_ends", ("a", "b"))


def _radius(problem: DesignProblem, spring, x: np.ndarray, default: float) -> float:
    """Capsule radius [m] of ``spring`` at design ``x``: half its coil's outer diameter, or ``default``."""
    values = problem.model.spring_values(spring, x)
    if "mean_diameter" in values and "wire_diameter" in values:
        return 0.5 * (values["mean_diameter"] + values["wire_diameter"])
    return default


class _Checker:
    """Distances of every two-point spring to the arm (and to each other) at a set of poses.

    Pose sets: 0 is the check set, 1 the 4× denser one, 2 the poses found by :meth:`descend`
    (local minima of a distance over the workspace's joint box, kept for the later rounds).
    """

    def __init__(self, problem: DesignProblem, clearance: Clearance):
        self.problem, self.clearance = problem, clearance
        mechanism = problem.mechanism
        self.scene = CollisionScene(mechanism, convex=True)
        base = problem.base_workspace
        self.bounds = [(float(np.min(base.joint_values[:, joint.index_v])),
                        float(np.max(base.joint_values[:, joint.index_v]))) for joint in mechanism.joints]
        ranges = {joint.name: list(bound) for joint, bound in zip(mechanism.joints, self.bounds)}
        n = clearance.check_samples
        self.joint_sets = [Workspace.sobol(mechanism, n=n, ranges=ranges, seed=0).joint_values,
                           Workspace.sobol(mechanism, n=4 * n, ranges=ranges, seed=1).joint_values]
        self.pose_sets = [mechanism.configurations(values) for values in self.joint_sets] + [[]]
        self.joint_sets.append([])
        self.springs = [spring for spring in problem.springs if getattr(spring, "ends", ()) == ("a", "b")]
        self.by_name = {spring.name: spring for spring in self.springs}
        self.checked = {spring.name: self.scene.indices_except([spring.anchors[e].body for e in _ends_of(spring)])
                        for spring in self.springs}
        self.frame_ids = {spring.name: tuple(mechanism.frame_id(spring.anchors[e].body) for e in _ends_of(spring))
                          for spring in self.springs}

    def _frames(self, spring):
        return tuple((np.array(self.scene.frame(f).rotation), np.array(self.scene.frame(f).translation))
                     for f in self.frame_ids[spring.name])

    def _ends(self, spring, frames, x, scenario):
        return [rotation @ self.problem.model.anchor_point(spring, end, x, scenario) + translation
                for end, (rotation, translation) in zip(_ends_of(spring), frames)]

    def _radii(self, x: np.ndarray) -> dict[str, float]:
        default = self.clearance.radius or DEFAULT_RADIUS
        return {s.name: _radius(self.problem, s, x, default) for s in self.springs}

    def _pairs(self):
        """Every pair checked: ``(kind, spring, object index or other spring, scenario)``."""
        for scenario in range(self.problem.model.n_scenarios):
            for spring in self.springs:
                for index in self.checked[spring.name]:
                    yield ("object", spring.name, index, scenario)
            if self.clearance.between_springs:
                for i, first in enumerate(self.springs):
                    for second in self.springs[i + 1:]:
                        yield ("spring", first.name, second.name, scenario)

    def _contact(self, pair, x: np.ndarray, radius: dict) -> tuple[Contact, tuple, tuple | None]:
        """Contact of ``pair`` at the placed pose, with the frames of its spring (and of the other spring)."""
        kind, first, second, scenario = pair
        spring = self.by_name[first]
        frames = self._frames(spring)
        ends = self._ends(spring, frames, x, scenario)
        if kind == "object":
            return self.scene.capsule_distance(*ends, radius[first], second), frames, None
        other = self.by_name[second]
        other_frames = self._frames(other)
        contact = capsule_contact(*ends, radius[first], *self._ends(other, other_frames, x, scenario), radius[second])
        return contact, frames, other_frames

    def measure(self, x: np.ndarray, pose_set: int):
        """Distances [m] of every pair at the poses of ``pose_set``.

        Returns ``(below, closest, nearest)``: ``below`` maps a key ``(*pair, pose_set, sample)``
        to its distance for every contact closer than the margin; ``closest`` maps a spring's name
        to its smallest distance; ``nearest`` maps a pair to its :data:`DESCENTS_PER_PAIR` closest
        ``(distance, pose_set, sample)``.
        """
        radius = self._radii(x)
        pairs = list(self._pairs())
        poses = self.pose_sets[pose_set]
        distances = np.full((len(poses), len(pairs)), np.inf)
        for sample, q in enumerate(poses):
            self.scene.place(q)
            for column, pair in enumerate(pairs):
                distances[sample, column] = self._contact(pair, x, radius)[0].distance
        below, closest, nearest = {}, {s.name: np.inf for s in self.springs}, {}
        for column, pair in enumerate(pairs):
            if not len(poses):
                break
            order = np.argsort(distances[:, column], kind="stable")
            nearest[pair] = [(float(distances[s, column]), pose_set, int(s)) for s in self._apart(pose_set, order)]
            names = (pair[1], pair[2]) if pair[0] == "spring" else (pair[1],)
            for name in names:
                closest[name] = min(closest[name], float(distances[order[0], column]))
            for sample in np.flatnonzero(distances[:, column] < self.clearance.margin):
                below[(*pair, pose_set, int(sample))] = float(distances[sample, column])
        return below, closest, nearest

    def _apart(self, pose_set: int, order) -> list[int]:
        """Up to :data:`DESCENTS_PER_PAIR` samples, closest first, at least a quarter of the joint box
        apart from each other (so the descents start in different basins)."""
        values = np.asarray(self.joint_sets[pose_set], dtype=float)
        span = np.array([high - low for low, high in self.bounds]) + 1e-12
        chosen: list[int] = []
        for sample in order:
            if all(np.linalg.norm((values[sample] - values[other]) / span) > 0.25 for other in chosen):
                chosen.append(int(sample))
                if len(chosen) == DESCENTS_PER_PAIR:
                    break
        return chosen

    def descend(self, x: np.ndarray, nearest: dict):
        """Search the joint box for the closest approach of every pair that comes near.

        From each of a pair's closest sampled poses within :data:`DESCENT_BAND` of the margin, a
        bounded quasi-Newton descent (SciPy's L-BFGS-B, finite differences of 0.1 mrad) minimises
        the pair's distance over the joint coordinates. Sampling alone misses the minima between
        samples (in 6-D, thousands of poses are far apart); the descent finds them. A minimum below
        the margin joins pose set 2 and is returned as ``below`` (as :meth:`measure` does).
        """
        from scipy.optimize import minimize

        radius = self._radii(x)
        mechanism = self.problem.mechanism
        below, closest = {}, {s.name: np.inf for s in self.springs}

        def distance(values, pair):
            self.scene.place(mechanism.configurations(values)[0])
            return self._contact(pair, x, radius)[0].distance

        for pair, starts in nearest.items():
            for start_distance, pose_set, sample in starts:
                if start_distance > self.clearance.margin + DESCENT_BAND:
                    continue
                start = np.asarray(self.joint_sets[pose_set][sample], dtype=float)
                found = minimize(distance, start, args=(pair,), method="L-BFGS-B", bounds=self.bounds,
                                 options={"eps": 1e-4, "maxfun": DESCENT_EVALUATIONS})
                value = float(distance(found.x, pair))
                names = (pair[1], pair[2]) if pair[0] == "spring" else (pair[1],)
                for name in names:
                    closest[name] = min(closest[name], value)
                if value < self.clearance.margin:
                    self.joint_sets[2].append(np.array(found.x))
                    self.pose_sets[2].append(mechanism.configurations(found.x)[0])
                    below[(*pair, 2, len(self.pose_sets[2]) - 1)] = value
        return below, closest

    def cuts(self, x: np.ndarray, keys) -> tuple[list, list]:
        """The cuts of the watched ``keys`` at design ``x``."""
        clearance = self.clearance
        radius = self._radii(x)
        object_cuts, spring_cuts = [], []
        for key in sorted(keys, key=lambda k: (k[4], k[5], k[:4])):
            pair, pose_set, sample = key[:4], key[4], key[5]
            kind, first, second, scenario = pair
            self.scene.place(self.pose_sets[pose_set][sample])
            contact, frames, other_frames = self._contact(pair, x, radius)
            spring = self.by_name[first]
            if kind == "object":
                label = f"{first} clear of {self.scene.objects[second].name} (pose {pose_set}:{sample})"
                object_cuts.append((label, spring, scenario, frames, contact, radius[first], clearance.target))
            else:
                spring_cuts.append((f"{first} clear of {second} (pose {pose_set}:{sample})",
                                    (spring, frames, radius[first]), (self.by_name[second], other_frames,
                                                                      radius[second]),
                                    scenario, contact, clearance.target))
        return object_cuts, spring_cuts


def _worst(below: dict) -> list:
    """Of the contacts below the margin, the :data:`WORST_PER_PAIR` closest per pair."""
    groups: dict = {}
    for key, distance in below.items():
        groups.setdefault(key[:4], []).append((distance, key))
    chosen = []
    for items in groups.values():
        chosen += [key for _, key in sorted(items)[:WORST_PER_PAIR]]
    return chosen


def fit_from_starts(problem: DesignProblem, solution: Solution, **solve_options) -> tuple[Solution, FitRecord]:
    """:func:`fit_to_arm` from the :attr:`Clearance.starts` best feasible designs of the multi-start
    (``solution.starts``, distinct, best first); keeps the converged fit of lowest objective (else the
    first), and leaves its rows on the problem."""
    count = problem.clearance.starts if problem.clearance is not None else 1
    records = sorted((record for record in solution.starts if record.feasible), key=lambda record: record.objective)
    others = [record for record in records if not np.array_equal(record.x, solution.x)][:count - 1]
    fits, initial_rows = [], problem.linear_rows   # the mounting rows of the multi-start, if any
    for x in [solution.x] + [record.x for record in others]:
        start = Solution(np.array(x, dtype=float), solution.starts, solution.method, solution.seed, solution.status)
        problem.linear_rows = initial_rows
        fitted, record = fit_to_arm(problem, start, **solve_options)
        fits.append((fitted, record, problem.linear_rows))
    converged = [fit for fit in fits if fit[1].converged] or fits[:1]
    fitted, record, rows = min(converged, key=lambda fit: fit[1].objective)
    problem.linear_rows = rows
    record.starts = len(fits)
    if len(fits) > 1:
        record.rounds = sum(fit[1].rounds for fit in fits)
        record.seconds = sum(fit[1].seconds for fit in fits)
    return fitted, record


def fit_to_arm(problem: DesignProblem, solution: Solution, **solve_options) -> tuple[Solution, FitRecord]:
    """Enforce the problem's clearance and mountings from ``solution`` (see the module documentation).

    ``solve_options`` go to :func:`~springbalance.design.solvers.solve_problem` (method, iterations).
    Returns the fitted solution and its :class:`FitRecord`.
    """
    clock = time.perf_counter()
    clearance = problem.clearance
    x = np.array(solution.x, dtype=float)
    before = problem.objective_value(problem.evaluate(x))
    checker = _Checker(problem, clearance) if clearance is not None else None
    geometry = collision_geometry(problem.mechanism) if problem.mounts else None
    watched: set = set()
    planes = mount_planes(problem, np.asarray(problem.variables.start, dtype=float)) if problem.mounts else {}
    rounds, converged, closest, mounts = 0, False, {}, {}
    limit = clearance.rounds if clearance is not None else 12
    while True:
        mounts = _mount_errors(problem, x, geometry) if problem.mounts else {}
        mounted = all(error <= MOUNT_ACCEPT for error in mounts.values())
        new = []
        if checker is not None:
            below, closest, nearest = checker.measure(x, 0)
            if checker.pose_sets[2]:
                found, nearby, _ = checker.measure(x, 2)
                below.update(found)
                closest = {name: min(closest[name], nearby[name]) for name in closest}
            if not below:
                below, dense, nearest_dense = checker.measure(x, 1)
                closest = {name: min(closest[name], dense[name]) for name in closest}
                nearest = nearest_dense             # 4× denser: its closest poses are the better starts
            if not below:
                below, searched = checker.descend(x, nearest)
                closest = {name: min(closest[name], searched[name]) for name in closest}
            new = [key for key in _worst(below) if key not in watched]
            converged = not below and mounted
        else:
            converged = mounted
        if converged or rounds >= limit:
            break
        watched.update(new)
        object_cuts, spring_cuts = checker.cuts(x, watched) if checker is not None else ([], [])
        planes = mount_planes(problem, x, planes)
        problem.linear_rows = _rows(problem, x, object_cuts, spring_cuts, planes)
        try:
            solution = solve_problem(problem, starts=1, initial=x, progress=False, **solve_options)
        except SolverError as error:
            # the linearised rows could not all be met from here: go on from the least violating
            # iterate (the next round rebuilds the rows there); the record says if it never clears
            if not error.starts:
                break
            least = min(error.starts, key=lambda record: record.max_violation)
            solution = Solution(least.x, solution.starts, solution.method, solution.seed,
                                f"{solution.status}; a fitting round stopped infeasible ({least.status})")
        x = np.array(solution.x, dtype=float)
        rounds += 1
    objective = problem.objective_value(problem.evaluate(x))
    poses = sum(len(poses) for poses in checker.pose_sets) if checker is not None else 0
    record = FitRecord(rounds, len(problem.linear_rows) if problem.linear_rows is not None else 0, bool(converged),
                       float(before), float(objective), {k: float(v) for k, v in closest.items()},
                       {k: float(v) for k, v in mounts.items()}, poses, time.perf_counter() - clock)
    status = (f"{solution.status}; fitted to the arm in {rounds} round(s)"
              + ("" if converged else " (NOT converged: see the clearance check)"))
    return Solution(x, solution.starts, solution.method, solution.seed, status), record
