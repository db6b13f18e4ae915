r"""Springs that run inside their own anchor link, beyond their anchor (the ``inside_own_link`` warning).

The clearance check (:mod:`springbalance.results.clearance`) and the clearance fit exempt a spring's two
anchor bodies: its anchors sit on them, so its capsule always touches them. That exemption also hides a
spring that runs *along inside* its own link, which no real spring can do. This check measures it.

For an end ``e`` of a two-point spring anchored at ``p`` on body ``B`` (with collision geometry; meshes
count as their convex hulls), at each pose of the design's workspace:

- the anchor's shortest way out of ``B`` is its depth ``d = max(0, -s_B(p))`` (``s_B``: signed distance
  to ``B``'s collision objects);
- the spring's own stretch at that end is ``d + r + `` :data:`OWN_STRETCH` along its axis (``r``: its capsule
  radius, half the coil's outer diameter, else 0.01 m): a spring that leaves ``B`` straight out has left it
  there; the same stretch is exempt at the other end (with that anchor's own depth in ``B``);
- the spring's centre line between the two stretches must not enter ``B``: its deepest point inside ``B``
  (coal's signed distance of the segment) is the ``depth`` [m] of the finding when it exceeds
  :data:`DEPTH_TOLERANCE`.

So a spring that leaves its link outward (within about 50° of the surface normal for a centre-line
anchor in a link as thick as the coil is wide) is not flagged, and one whose centre line runs on inside
the link is. Only designs whose URDF has collision geometry are checked; the result is computed once per
design.
"""

from __future__ import annotations

import dataclasses
import weakref
from typing import Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.model.collision import CollisionScene, capsule_radius, collision_geometry
from springbalance.model.inside_link import DEPTH_TOLERANCE, OWN_STRETCH, centre_line_inside
from springbalance.model.surfaces import surface_distance

__all__ = ["DEPTH_TOLERANCE", "OWN_STRETCH", "OwnLinkFinding", "inside_own_link"]
_CACHE: weakref.WeakKeyDictionary[EvaluatedDesign, list[OwnLinkFinding]] = weakref.WeakKeyDictionary()


@dataclasses.dataclass(frozen=True)
class OwnLinkFinding:
    """A spring whose centre line runs inside its own anchor link beyond its anchor.

    Attributes:
        spring: the spring's name; ``end``: the end anchored on ``body``.
        body: the anchor body (URDF link) it runs inside.
        depth: how deep its centre line lies inside the body there, at most over the poses [m].
        pose: the joint values [rad or m] of that pose (joint name → value); ``sample``: its index.
        scenario: the scenario whose anchors these are (None when every scenario has the same).
    """

    spring: str
    end: str
    body: str
    depth: float
    pose: dict[str, float]
    sample: int
    scenario: str | None


def inside_own_link(result: EvaluatedDesign) -> list[OwnLinkFinding]:
    """Every spring end of ``result`` whose spring runs inside its anchor body (see the module documentation);
    empty when the arm's URDF has no collision geometry. Computed once per design."""
    if result not in _CACHE:
        _CACHE[result] = _findings(result)
    return _CACHE[result]


def _findings(result: EvaluatedDesign) -> list[OwnLinkFinding]:
    problem = result.problem
    mechanism = problem.mechanism
    try:
        geometry = collision_geometry(mechanism)
    except InputError:
        return []
    scene = CollisionScene(mechanism, geometry, convex=True)
    ends = _ends(result, scene, geometry)
    if not ends:
        return []
    joint_values = problem.base_workspace.joint_values
    worst: dict[tuple[str, str, str | None], tuple[float, int]] = {}
    for sample, q in enumerate(mechanism.configurations(joint_values)):
        scene.place(q)
        for end in ends:
            depth = _depth(scene, end)
            key = (end["spring"], end["end"], end["scenario"])
            if depth > DEPTH_TOLERANCE and depth > worst.get(key, (0.0, -1))[0]:
                worst[key] = (depth, sample)
    by_key = {(end["spring"], end["end"], end["scenario"]): end for end in ends}
    return [
        OwnLinkFinding(
            spring,
            name,
            by_key[(spring, name, scenario)]["body"],
            depth,
            {joint.name: float(joint_values[sample, joint.index_v]) for joint in mechanism.joints},
            sample,
            scenario,
        )
        for (spring, name, scenario), (depth, sample) in worst.items()
    ]


def _ends(result: EvaluatedDesign, scene: CollisionScene, geometry: Any) -> list[dict[str, Any]]:
    """Per spring end anchored on a body with collision objects (and per scenario with its own anchors): the
    body's objects, the frames of both ends, both anchor points [m], the capsule radius [m] and the anchor's
    depth in its body [m]."""
    problem = result.problem
    mechanism = problem.mechanism
    names: list[str | None] = [scenario.name for scenario in problem.scenarios] or [None]
    found: list[dict[str, Any]] = []
    for spring, record in zip(problem.springs, result.springs):
        if "a" not in record or "b" not in record:
            continue  # a torsional spring acts inside its joint
        pair = getattr(spring, "spring_ends", ("a", "b"))  # a routed spring: its first segment
        bodies = [record[end]["body"] for end in pair]
        variants: list[tuple[str | None, list[np.ndarray]]] = []
        for index, scenario in enumerate(names):
            points = [np.asarray(problem.model.anchor_point(spring, end, result.x, index), dtype=float) for end in pair]
            if not any(all(np.array_equal(p, q) for p, q in zip(points, seen)) for _, seen in variants):
                variants.append((scenario, points))
        if len(variants) == 1:
            variants = [(None, variants[0][1])]
        for own in (0, 1):
            objects = [i for i, link in enumerate(scene.bodies) if link == bodies[own]]
            if not objects:
                continue
            for scenario, points in variants:
                found.append(
                    {
                        "spring": str(spring.name),
                        "end": pair[own],
                        "body": bodies[own],
                        "scenario": scenario,
                        "objects": objects,
                        "frames": [mechanism.frame_id(bodies[own]), mechanism.frame_id(bodies[1 - own])],
                        "points": [points[own], points[1 - own]],
                        "radius": capsule_radius(record),
                        "inside": max(0.0, -surface_distance(mechanism, geometry, bodies[own], points[own])[0]),
                    }
                )
    return found


def _depth(scene: CollisionScene, end: dict[str, Any]) -> float:
    """How deep [m] the spring's centre line, less the stretches at both ends, lies inside the end's body at
    the placed pose (0 when it does not enter it; :func:`~springbalance.model.inside_link.centre_line_inside`)."""
    own, other = (scene.frame(frame).act(point) for frame, point in zip(end["frames"], end["points"]))
    return centre_line_inside(scene, own, other, end["objects"], end["inside"], end["radius"])[0]
