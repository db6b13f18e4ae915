"""The bracket an anchor needs when it stands off its link (:func:`bracket`, :func:`spring_brackets`; docs/model.md §11).

An anchor lies where its region puts it in its body's frame: on the link's surface (``on: collision``), or
anywhere in a box, which may reach far from the link. A spring end there is held by a bracket from the link
that the design does not include:

- not its mass: the gravity the springs balance is the arm's;
- not its stiffness: a spring force ``F`` [N] at the end of a bracket of length ``d`` [m] bends its root by
  the moment ``F·d`` [N·m], and the anchor moves as the bracket bends;
- not its clearance: the springs alone are kept clear of the links.

The bracket here is the straight segment from the anchor to the nearest point of its link's collision geometry
(meshes as their convex hulls, :func:`~springbalance.model.surfaces.surface_distance`): the shortest one it
can be. Where that segment passes through another link at some pose (:func:`bracket_crossings`), the bracket
must go round it. Lengths in m; points in the link's (body's) frame.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Iterable, Mapping

import numpy as np
import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model.collision import CollisionScene, collision_geometry
from springbalance.model.mechanism import Mechanism
from springbalance.model.surfaces import body_objects, surface_distance


@dataclasses.dataclass(frozen=True)
class Bracket:
    """A bracket from a link's surface to an anchor.

    Attributes:
        body: the link that carries it.
        anchor: the anchor point, body frame [m] (3).
        foot: the nearest point of the link's collision geometry, body frame [m] (3).
        length: the distance from the foot to the anchor [m] (> 0).
    """

    body: str
    anchor: np.ndarray
    foot: np.ndarray
    length: float


def bracket(mechanism: Mechanism, geometry: pin.GeometryModel, body: str, point: np.ndarray) -> Bracket | None:
    """The bracket that holds ``point`` (body frame [m]) off ``body``; None on the ground (the base or a post
    is the mounting's business), on a link without collision geometry, and for a point on or inside the link."""
    if mechanism.is_ground(body) or not body_objects(mechanism, geometry, body):
        return None
    anchor = np.asarray(point, dtype=float)
    distance, foot, _ = surface_distance(mechanism, geometry, body, anchor)
    if distance <= 0.0:
        return None
    return Bracket(body, anchor, np.asarray(foot, dtype=float), float(distance))


def spring_brackets(mechanism: Mechanism, springs: Iterable[Mapping[str, Any]]) -> dict[tuple[str, str], Bracket]:
    """The brackets of the ends of two-point springs, by ``(spring name, end)``, from spring records (a design's
    :attr:`~springbalance.design.evaluated.EvaluatedDesign.springs`: ``{"name", "a": {"body", "point"}, "b": …}``;
    records without ends, torsional springs, are skipped). Empty for an arm without collision geometry."""
    try:
        geometry = collision_geometry(mechanism)
    except InputError:  # no URDF, or no <collision> elements: nothing to measure
        return {}
    found = {}
    for record in springs:
        for end in ("a", "b"):
            anchor = record.get(end)
            if not isinstance(anchor, Mapping) or "point" not in anchor:
                continue
            held = bracket(mechanism, geometry, anchor["body"], np.asarray(anchor["point"], dtype=float))
            if held is not None:
                found[(str(record["name"]), end)] = held
    return found


#: a bracket's line that overlaps another link by less than this [m] only touches it (where two links meet)
TOUCH = 1e-4


@dataclasses.dataclass(frozen=True)
class Crossing:
    """The deepest pass of a bracket's straight line through another link.

    Attributes:
        link: the link it passes through.
        depth: how deep [m] (the overlap of the line with the link's convex hull, > 0).
        pose: the index of the configuration where it is deepest.
    """

    link: str
    depth: float
    pose: int


def bracket_crossings(
    mechanism: Mechanism, brackets: Mapping[Any, Bracket], configurations: np.ndarray
) -> dict[Any, Crossing]:
    """For each of ``brackets`` (by key) whose straight line passes through a link other than its own at one of
    ``configurations`` (N×nq), the deepest such pass; meshes count as their convex hulls."""
    deepest = {}
    for key, (depths, links) in bracket_depths(mechanism, brackets, configurations).items():
        pose = int(np.argmax(depths))
        if depths[pose] > 0.0:
            deepest[key] = Crossing(links[pose], float(depths[pose]), pose)
    return deepest


def bracket_depths(
    mechanism: Mechanism, brackets: Mapping[Any, Bracket], configurations: np.ndarray
) -> dict[Any, tuple[np.ndarray, list[str]]]:
    """For each of ``brackets`` (by key), how deep [m] its straight line passes through a link other than its own
    at each of ``configurations`` (N×nq; 0 where it passes through none, or only touches one: :data:`TOUCH`) and
    through which link (``""`` there); meshes count as their convex hulls."""
    configurations = np.asarray(configurations, dtype=float)
    found = {key: (np.zeros(len(configurations)), [""] * len(configurations)) for key in brackets}
    if not brackets:
        return found
    scene = CollisionScene(mechanism, collision_geometry(mechanism), convex=True)
    objects = {key: scene.indices_except([held.body]) for key, held in brackets.items()}
    frames = {key: mechanism.frame_id(held.body) for key, held in brackets.items()}
    for pose, configuration in enumerate(configurations):
        scene.place(configuration)  # the frames too: each bracket moves with its link
        for key, held in brackets.items():
            placement = scene.frame(frames[key])
            foot, anchor = placement.act(held.foot), placement.act(held.anchor)
            depths, links = found[key]
            for index in objects[key]:
                depth = -scene.capsule_distance(foot, anchor, 0.0, index).distance
                if depth > max(depths[pose], TOUCH):
                    depths[pose], links[pose] = depth, scene.links[index]
    return found
