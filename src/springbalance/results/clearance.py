"""Clearance check of a finished design: do its springs stay clear of the arm?

Every two-point spring is modelled as a capsule (a cylinder with hemispherical ends) of
radius ``r`` around the straight line between its two world end points: ``r`` is half the
coil's ``outer_diameter`` for a helical spring (its spec sheet), otherwise the ``radius``
given (default 0.01 m). At every pose of the design's workspace (or of a denser Sobol sample
of the same joint ranges) the signed distance [m] from the capsule to every collision object
of the arm's URDF (``<collision>`` elements, loaded by Pinocchio) is computed with coal
(``coal.distance``); it is negative when they overlap (the penetration depth).

**Exemption.** A spring's anchors sit on the two bodies it is attached to, so its capsule
always touches (or enters) their collision shapes; the collision objects of exactly those two
bodies are left out of its check. Links welded to them (by a fixed joint) are still checked,
and so is every other link. An end on ``universe`` exempts nothing else: a base link with
collision geometry is checked.

For mesh collision geometry coal measures to the triangle surface: an overlap reads 0 or a
small negative depth, and a capsule lying wholly inside a closed mesh, touching none of its
triangles, is not seen. Box, cylinder, sphere and capsule shapes give exact signed distances.

:func:`checked_clearance` is the check the reports and the ``overlap`` failure
(:mod:`springbalance.results.failure_flags`) share: computed once per design object and design vector.

This is the independent check of a finished design. The optimisation's own clearance
constraint (:mod:`springbalance.design.clearance`) is linearised from the same distances.
"""

from __future__ import annotations

import dataclasses
import weakref
from typing import Any, Iterable

import numpy as np
import pinocchio as pin

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.problem import DesignProblem
from springbalance.errors import InputError
from springbalance.export.common import spring_name
from springbalance.model.collision import CollisionScene, capsule_radius, collision_geometry
from springbalance.model.floor import FLOOR
from springbalance.model.workspace import Workspace


@dataclasses.dataclass(frozen=True)
class ClearanceRow:
    """The clearance of one spring over the poses checked.

    Attributes:
        spring: the spring's name.
        radius: capsule radius [m] (half the coil's outer diameter, or the radius given).
        distance: smallest signed distance [m] from the capsule to a checked collision object
            over the poses; negative when they overlap; ``inf`` when there is nothing to check.
        link: the body (URDF link) of the closest collision object (None when nothing is checked).
        geometry: the name of that collision object (Pinocchio's ``<link>_<i>``).
        pose: joint values where the smallest distance occurs, joint name → rad (revolute,
            continuous) or m (prismatic).
        sample: index of that pose among the poses checked.
        scenario: the scenario in which it occurs, when the anchors differ per scenario (else None).
        exempt: the bodies whose collision objects are not checked (the spring's anchor bodies).
        below_margin: True when ``distance`` is below the margin, or ≤ 0 (contact).
    """

    spring: str
    radius: float
    distance: float
    link: str | None
    geometry: str | None
    pose: dict[str, float]
    sample: int | None
    scenario: str | None
    exempt: tuple[str, str]
    below_margin: bool

    def to_dict(self) -> dict[str, Any]:
        """The row as JSON-friendly data (``distance`` None when nothing is checked)."""
        record = dataclasses.asdict(self)
        record["exempt"] = list(self.exempt)
        record["distance"] = self.distance if np.isfinite(self.distance) else None
        return record


@dataclasses.dataclass(frozen=True)
class ClearanceReport:
    """Per spring, how close its capsule comes to the arm's collision geometry.

    Attributes:
        rows: one :class:`ClearanceRow` per two-point spring, in the design's order.
        margin: the clearance asked for [m].
        poses: the number of poses checked.
        mechanism: the mechanism's name.
        collision_objects: names of the arm's collision objects.
        skipped: springs that are not checked (torsional springs act inside a joint).
        joint_units: joint name → ``"rad"`` or ``"m"`` (the unit of the pose values).
    """

    rows: list[ClearanceRow]
    margin: float
    poses: int
    mechanism: str
    collision_objects: list[str]
    skipped: list[str] = dataclasses.field(default_factory=list)
    joint_units: dict[str, str] = dataclasses.field(default_factory=dict)

    @property
    def clear(self) -> bool:
        """True when every spring keeps at least ``margin`` from the arm."""
        return not any(row.below_margin for row in self.rows)

    def row(self, spring: str) -> ClearanceRow:
        """The row of the spring called ``spring``."""
        for row in self.rows:
            if row.spring == spring:
                return row
        raise InputError(f"no clearance row for spring {spring!r}; springs: {', '.join(r.spring for r in self.rows)}")

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-friendly data (lengths in m, joint values in rad or m)."""
        return {
            "mechanism": self.mechanism,
            "margin": self.margin,
            "poses": self.poses,
            "clear": self.clear,
            "collision_objects": list(self.collision_objects),
            "skipped": list(self.skipped),
            "rows": [row.to_dict() for row in self.rows],
        }

    def cells(self, row: ClearanceRow) -> list[str]:
        """One row of the table as text: spring, radius [mm], clearance [mm], closest link, status,
        pose (angles in degrees, prismatic joints in m)."""
        if np.isfinite(row.distance):
            distance = f"{row.distance * 1e3:.1f}"
            status = (
                "OVERLAP"
                if row.distance < 0
                else "CONTACT"
                if row.distance == 0
                else "below margin"
                if row.below_margin
                else "ok"
            )
        else:
            distance, status = "-", "nothing to check"
        pose = ", ".join(
            f"{name}={value:.4g} m" if self.joint_units.get(name) == "m" else f"{name}={np.degrees(value):.1f}°"
            for name, value in row.pose.items()
        )
        if row.scenario is not None:
            pose = f"{pose} ({row.scenario})"
        return [row.spring, f"{row.radius * 1e3:.1f}", distance, row.link or "-", status, pose or "-"]

    def lines(self) -> list[str]:
        """The report as text: a header, a table with one line per spring and a verdict.

        Distances are printed in mm, the pose's angles in degrees and prismatic joints in m.
        """
        floor = " and to the floor" if FLOOR in self.collision_objects else ""
        header = (
            f"Clearance of the springs to the collision geometry of {self.mechanism!r}{floor} "
            f"over {self.poses} poses (margin {self.margin * 1e3:.1f} mm; a spring's anchor bodies are exempt)"
        )
        table = [["spring", "radius [mm]", "clearance [mm]", "closest link", "status", "at pose"]]
        table += [self.cells(row) for row in self.rows]
        widths = [max(len(line[column]) for line in table) for column in range(len(table[0]))]
        text = [header, ""]
        text += ["  ".join(cell.ljust(width) for cell, width in zip(line, widths)).rstrip() for line in table]
        if self.skipped:
            text.append(f"not checked (they act in a joint): {', '.join(self.skipped)}")
        below = [row.spring for row in self.rows if row.below_margin]
        text.append("")
        text.append(
            f"Clearance: {len(below)} of {len(self.rows)} springs below the margin ({', '.join(below)})"
            if below
            else f"Clearance: every spring clear by at least {self.margin * 1e3:.1f} mm"
        )
        return text

    def __str__(self) -> str:
        return "\n".join(self.lines())


def clearance(
    result: EvaluatedDesign,
    radius: float | None = None,
    samples: int | None = None,
    margin: float | None = None,
    geometry: pin.GeometryModel | None = None,
) -> ClearanceReport:
    """Smallest distance from each spring of ``result`` to the arm's collision geometry.

    See the module documentation for the model (capsules, signed distances, the exemption of
    a spring's two anchor bodies).

    Args:
        result: the finished design.
        radius: capsule radius [m] of the springs without a helical spec sheet (default
            0.01 m); a helical spring's capsule has half its outer diameter.
        samples: check this many scrambled Sobol poses (seed 0) over the smallest and largest
            value of each joint in the design's workspace instead of the workspace's own poses.
        margin: the clearance asked for [m], ≥ 0; a row is flagged ``below_margin`` when its
            distance is below it. Default: the problem's :class:`~springbalance.design.clearance.Clearance`
            margin when it has one, else 0 (and its ``radius`` is then the default radius).
        geometry: the arm's collision geometry, when already loaded (:func:`collision_geometry`).

    Returns:
        The :class:`ClearanceReport`.

    Raises:
        InputError: a bad ``radius``, ``samples`` or ``margin``, or a mechanism without a URDF
            or without collision geometry.
    """
    margin, radius = _checked_options(result.problem, radius, samples, margin)
    problem = result.problem
    mechanism = problem.mechanism
    scene = CollisionScene(mechanism, collision_geometry(mechanism) if geometry is None else geometry)
    joint_values = _poses(problem, samples)
    configurations = mechanism.configurations(joint_values)
    capsules, skipped = _capsules(result, scene, radius)
    _closest_approach(scene, capsules, configurations)
    objects, links = scene.objects, scene.links
    rows = []
    for capsule in capsules:
        distance, index, sample, scenario = capsule["best"]
        pose = (
            {joint.name: float(joint_values[sample, joint.index_v]) for joint in mechanism.joints}
            if sample is not None
            else {}
        )
        rows.append(
            ClearanceRow(
                spring=capsule["name"],
                radius=capsule["radius"],
                distance=distance,
                link=links[index] if index is not None else None,
                geometry=objects[index].name if index is not None else None,
                pose=pose,
                sample=sample,
                scenario=scenario,
                exempt=capsule["bodies"],
                below_margin=bool(np.isfinite(distance) and (distance < margin or distance <= 0)),
            )
        )
    return ClearanceReport(
        rows=rows,
        margin=float(margin),
        poses=int(joint_values.shape[0]),
        mechanism=mechanism.name,
        collision_objects=[obj.name for obj in objects],
        skipped=skipped,
        joint_units={joint.name: joint.unit for joint in mechanism.joints},
    )


#: design → (its design vector's bytes, its check) of :func:`checked_clearance`
_CHECKED: weakref.WeakKeyDictionary[EvaluatedDesign, tuple[bytes, ClearanceReport | None]] = weakref.WeakKeyDictionary()


def checked_clearance(result: EvaluatedDesign) -> ClearanceReport | None:
    """The clearance check of ``result`` over its workspace's poses (:func:`clearance` with the problem's
    options) when its arm's URDF has collision geometry; None when it has none (or the mechanism has no
    URDF): nothing to check. Computed once per design object (again when its ``x`` changes)."""
    key = np.asarray(result.x, dtype=float).tobytes()
    cached = _CHECKED.get(result)
    if cached is not None and cached[0] == key:
        return cached[1]
    try:
        geometry = collision_geometry(result.problem.mechanism)
    except InputError:
        report = None
    else:
        report = clearance(result, geometry=geometry)
    _CHECKED[result] = (key, report)
    return report


def _checked_options(
    problem: DesignProblem, radius: float | None, samples: int | None, margin: float | None
) -> tuple[float, float | None]:
    """``(margin, radius)`` [m] of the check: the ones given, else the problem's clearance options; InputError
    naming a bad ``radius``, ``margin`` or ``samples``."""
    asked = problem.clearance
    if margin is None:
        margin = asked.margin if asked is not None else 0.0
    if radius is None and asked is not None:
        radius = asked.radius
    if radius is not None and not (np.isfinite(radius) and radius > 0):
        raise InputError(f"clearance radius must be a finite number > 0 [m], got {radius!r}")
    if not (np.isfinite(margin) and margin >= 0):
        raise InputError(f"clearance margin must be a finite number ≥ 0 [m], got {margin!r}")
    if samples is not None and (isinstance(samples, bool) or int(samples) != samples or samples < 1):
        raise InputError(f"clearance samples must be an integer ≥ 1, got {samples!r}")
    return margin, radius


def _poses(problem: DesignProblem, samples: int | None) -> np.ndarray:
    """The joint values (N×nv) [rad or m] to check: the base workspace's, or ``samples`` scrambled Sobol
    poses (seed 0) over its smallest and largest value of each joint."""
    mechanism, base = problem.mechanism, problem.base_workspace
    if samples is None:
        return base.joint_values
    ranges = {
        joint.name: [
            float(np.min(base.joint_values[:, joint.index_v])),
            float(np.max(base.joint_values[:, joint.index_v])),
        ]
        for joint in mechanism.joints
    }
    return Workspace.sobol(mechanism, n=int(samples), ranges=ranges, seed=0).joint_values


def _capsules(
    result: EvaluatedDesign, scene: CollisionScene, radius: float | None
) -> tuple[list[dict[str, Any]], list[str]]:
    """The capsules: per two-point spring, its radius [m], exempt bodies, their frames, the collision objects
    it is checked against and the anchor points [m] of each scenario (one per distinct pair); and the names
    of the springs not checked (torsional)."""
    problem = result.problem
    mechanism = problem.mechanism
    scenario_names: list[str | None] = [scenario.name for scenario in problem.scenarios] or [None]
    capsules: list[dict[str, Any]] = []
    skipped: list[str] = []
    for spring, record in zip(problem.springs, result.springs):
        if "a" not in record or "b" not in record:
            skipped.append(spring_name(spring))
            continue
        spring_radius = capsule_radius(record, radius)
        ends = getattr(spring, "spring_ends", ("a", "b"))  # a routed spring: its first segment
        bodies = tuple(record[end]["body"] for end in ends)
        # (scenario name, point a, point b), one per distinct pair of anchor points
        variants: list[tuple[str | None, np.ndarray, np.ndarray]] = []
        for index, name in enumerate(scenario_names):
            point_a, point_b = (
                np.asarray(problem.model.anchor_point(spring, end, result.x, scenario=index), dtype=float)
                for end in ends
            )
            if not any(np.array_equal(point_a, a) and np.array_equal(point_b, b) for _, a, b in variants):
                variants.append((name, point_a, point_b))
        if len(variants) == 1:
            variants = [(None, variants[0][1], variants[0][2])]
        capsules.append(
            {
                "name": spring.name,
                "radius": spring_radius,
                "bodies": bodies,
                "variants": variants,
                "frames": tuple(mechanism.frame_id(body) for body in bodies),
                "checked": scene.indices_except(bodies),
                "best": (np.inf, None, None, None),
            }
        )
    return capsules, skipped


def _closest_approach(
    scene: CollisionScene, capsules: list[dict[str, Any]], configurations: Iterable[np.ndarray]
) -> None:
    """Set each capsule's ``best``: (smallest signed distance [m], collision object index, sample, scenario)
    over the configurations."""
    for sample, q in enumerate(configurations):
        scene.place(q)
        for capsule in capsules:
            frame_a, frame_b = capsule["frames"]
            for scenario, point_a, point_b in capsule["variants"]:
                start = scene.frame(frame_a).act(point_a)
                end = scene.frame(frame_b).act(point_b)
                for index in capsule["checked"]:
                    distance = scene.capsule_distance(start, end, capsule["radius"], index).distance
                    if distance < capsule["best"][0]:
                        capsule["best"] = (distance, index, sample, scenario)
