"""A workspace that takes the arm through its own floor (``arm_through_floor``, a warning).

With a floor (``mechanism.floor``, :mod:`springbalance.model.floor`) the springs keep clear of it, but nothing in
the solve keeps the arm's own links above it: the workspace is the user's. At every pose of the workspace (its
samples, before any scenarios are stacked) each collision object of a moving link (not the ground's, nor a link
welded to it: the base stands on the floor) is measured against the floor, as its convex hull, by coal; a link more
than :data:`FLOOR_TOLERANCE` [m] below it is through it. A table-mounted arm cannot take such a pose, yet the design
balances it and keeps its springs above the floor there: the warning names the deepest link, by how much and where,
and how many poses do it.
"""

from __future__ import annotations

import weakref

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.problem import DesignProblem
from springbalance.model.collision import CollisionScene, collision_geometry
from springbalance.model.floor import FLOOR
from springbalance.results.flag import Flag
from springbalance.results.verification_report import pose_text

#: a link this far below the floor [m] or less touches it (the UR5's base mesh reaches 3 mm below its underside)
FLOOR_TOLERANCE = 0.005


#: problem → its flags: they depend on the mechanism and the workspace alone, and a design's findings are asked for
#: several times (three in a run of ``springbalance design``)
_FOUND: weakref.WeakKeyDictionary[DesignProblem, list[Flag]] = weakref.WeakKeyDictionary()


def arm_through_floor_flags(result: EvaluatedDesign) -> list[Flag]:
    """``arm_through_floor``: one warning when links of the arm pass through its floor at poses of the workspace."""
    problem = result.problem
    if problem.mechanism.floor is None:
        return []
    if problem not in _FOUND:
        _FOUND[problem] = _through_floor(problem)
    return list(_FOUND[problem])


def _through_floor(problem: DesignProblem) -> list[Flag]:
    """:func:`arm_through_floor_flags` of ``problem``'s workspace."""
    mechanism = problem.mechanism
    joint_values = problem.base_workspace.joint_values
    depths, deepest = _depths(CollisionScene(mechanism, collision_geometry(mechanism), convex=True), joint_values)
    through = depths > FLOOR_TOLERANCE
    if not np.any(through):
        return []
    sample = int(np.argmax(depths))
    pose = {joint.name: float(joint_values[sample, joint.index_v]) for joint in mechanism.joints}
    units = {joint.name: joint.unit for joint in mechanism.joints}
    return [
        Flag(
            "arm_through_floor",
            "workspace",
            f"the arm passes through its floor (z = {mechanism.floor:g} m) at {int(np.sum(through))} of "
            f"{len(depths)} workspace poses, {deepest[sample]} deepest by {1e3 * depths[sample]:.1f} mm at "
            f"{pose_text(pose, units)}: an arm that stands on it cannot take those poses, yet the design balances "
            "them (and keeps its springs above the floor there)",
            "narrow workspace.ranges, or add workspace.couplings that keep the arm above the floor, so that the "
            "design is balanced where the arm moves",
        )
    ]


def _depths(scene: CollisionScene, joint_values: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Per pose, how deep [m] the arm's moving links reach below the floor (≤ 0: above it) and the deepest link."""
    mechanism = scene.mechanism
    floor = scene.links.index(FLOOR)
    moving = [i for i, body in enumerate(scene.bodies) if i != floor and not mechanism.is_ground(body)]
    depths, deepest = np.zeros(joint_values.shape[0]), [""] * joint_values.shape[0]
    for sample, q in enumerate(mechanism.configurations(joint_values)):
        scene.place(q)
        for index in moving:
            distance = scene.between(index, floor)
            if -distance > depths[sample]:
                depths[sample], deepest[sample] = -distance, scene.links[index]
    return depths, deepest
