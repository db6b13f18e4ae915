r"""Candidate spring places for a study: which two bodies a spring may join, and where on each.

A **candidate** joins body ``a`` (nearer the ground) to body ``b``, each end free in a box of its
body's frame. ``candidates: auto`` takes, on a URDF's kinematic tree,

- the ground to every moving body (a spring from the frame reaches any link);
- every body to each of its descendants at most ``span`` joints further out (parent → child is
  span 1; a spring across the elbow from the upper arm to the wrist is span 2);

with one body per joint: links welded to each other (fixed joints) move as one, so a spring to
either is the same candidate (the first link after the joint stands for them). Each end's box is
the bounding box of its body's collision geometry grown by ``margin`` [m], or, for a body without
collision geometry (and the ground), the cube of half-width ``default`` [m] about the body frame's
origin.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Sequence

import pinocchio as pin

from springbalance.design.mounts import body_bounds
from springbalance.errors import InputError
from springbalance.model.collision import collision_geometry
from springbalance.model.mechanism import GROUND, Mechanism
from springbalance.springs.params import Free, anchor_from_dict

#: half-width [m] of an end's box on a body without collision geometry
DEFAULT_HALF_WIDTH = 0.3
#: growth [m] of a body's collision bounding box
DEFAULT_MARGIN = 0.05


@dataclasses.dataclass(frozen=True)
class Candidate:
    """One place a spring may go: body ``a`` to body ``b``, each end free in its box (body frame, [m]).

    ``span`` is the number of joints between the two bodies.
    """

    a: str
    b: str
    box_a: tuple[tuple[float, ...], tuple[float, ...]]
    box_b: tuple[tuple[float, ...], tuple[float, ...]]
    span: int

    @property
    def label(self) -> str:
        return f"{self.a}→{self.b}"

    def anchors(self) -> tuple[dict, dict]:
        """The two ends as anchor records ``{body, box: {lower, upper}}``."""
        a, b = (
            {"body": body, "box": {"lower": list(box[0]), "upper": list(box[1])}}
            for body, box in ((self.a, self.box_a), (self.b, self.box_b))
        )
        return a, b

    def to_dict(self) -> dict[str, Any]:
        a, b = self.anchors()
        return {"a": a, "b": b, "span": self.span}


class BodyTree:
    """The mechanism's bodies as a tree of joints: one representative body per joint (0: the ground)."""

    def __init__(self, mechanism: Mechanism):
        model = mechanism.model
        self.mechanism = mechanism
        self.joint_of: dict[str, int] = {}
        self.body_of: dict[int, str] = {0: GROUND}
        for body in mechanism.body_names:
            joint = int(model.frames[mechanism.frame_id(body)].parentJoint)
            self.joint_of[body] = joint
            self.body_of.setdefault(joint, body)
        self.parent = {joint: int(model.parents[joint]) for joint in range(1, model.njoints)}

    def ancestors(self, joint: int) -> list[int]:
        """The joints from ``joint``'s parent down to the ground (0)."""
        chain = []
        while joint != 0:
            joint = self.parent[joint]
            chain.append(joint)
        return chain

    def span(self, first: int, second: int) -> int:
        """Joints between two bodies (through their nearest common ancestor)."""
        up_first, up_second = [first] + self.ancestors(first), [second] + self.ancestors(second)
        common = next(joint for joint in up_first if joint in up_second)
        return up_first.index(common) + up_second.index(common)

    def representative(self, body: str) -> str:
        """The body that stands for ``body``'s joint (``universe`` for every ground body)."""
        return self.body_of[self.joint_of[body]]


def _geometry(mechanism: Mechanism) -> pin.GeometryModel | None:
    """The URDF's collision geometry, or None when it has none (the boxes are then cubes)."""
    try:
        return collision_geometry(mechanism)
    except InputError:
        return None


def _box(
    mechanism: Mechanism, geometry: pin.GeometryModel | None, body: str, margin: float, default: float
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    if geometry is not None and not mechanism.is_ground(body):
        try:
            lower, upper = body_bounds(mechanism, geometry, body)
            return tuple(map(float, lower - margin)), tuple(map(float, upper + margin))
        except InputError:
            pass  # no collision geometry on this body
    return (-default,) * 3, (default,) * 3


def auto_candidates(
    mechanism: Mechanism, span: int = 2, margin: float = DEFAULT_MARGIN, default: float = DEFAULT_HALF_WIDTH
) -> list[Candidate]:
    """The ``auto`` candidates of ``mechanism`` (see the module documentation), ground pairs first."""
    if isinstance(span, bool) or not isinstance(span, int) or span < 1:
        raise InputError(f"explore.span must be an integer ≥ 1 (joints a spring may cross), got {span!r}")
    tree, geometry = BodyTree(mechanism), _geometry(mechanism)
    moving = sorted(joint for joint in tree.body_of if joint != 0)
    pairs = [(0, joint) for joint in moving]
    for joint in moving:
        for ancestor in tree.ancestors(joint)[:-1]:  # moving ancestors only (the ground is above)
            if tree.span(ancestor, joint) <= span:
                pairs.append((ancestor, joint))
    candidates = []
    for first, second in dict.fromkeys(pairs):
        a, b = tree.body_of[first], tree.body_of[second]
        candidates.append(
            Candidate(
                a,
                b,
                _box(mechanism, geometry, a, margin, default),
                _box(mechanism, geometry, b, margin, default),
                tree.span(first, second),
            )
        )
    return candidates


def candidates_from_records(
    mechanism: Mechanism,
    records: Sequence,
    margin: float = DEFAULT_MARGIN,
    default: float = DEFAULT_HALF_WIDTH,
    where: str = "explore.candidates",
) -> list[Candidate]:
    """Candidates a config names: ``[body_a, body_b]`` (boxes as for ``auto``) or ``{a: anchor, b: anchor}``
    with boxes. Bodies welded to each other count once (a repeated candidate is an error)."""
    if not isinstance(records, list) or not records:
        raise InputError(f"{where}: expected 'auto' or a non-empty list of body pairs, got {records!r}")
    tree, geometry = BodyTree(mechanism), _geometry(mechanism)
    candidates: list[Candidate] = []
    seen: dict[tuple[int, ...], int] = {}
    for i, record in enumerate(records):
        here = f"{where}[{i}]"
        if isinstance(record, list) and len(record) == 2 and all(isinstance(b, str) for b in record):
            ends = []
            for body in record:
                if body not in mechanism.body_names:
                    raise InputError(
                        f"{here}: unknown body {body!r} in mechanism {mechanism.name!r}; bodies: "
                        f"{', '.join(mechanism.body_names)}"
                    )
                ends.append((body, _box(mechanism, geometry, body, margin, default)))
        elif isinstance(record, dict) and set(record) == {"a", "b"}:
            ends = []
            for end in ("a", "b"):
                anchor = anchor_from_dict(record[end], f"{here}.{end}")
                if anchor.body not in mechanism.body_names:
                    raise InputError(
                        f"{here}.{end}.body: unknown body {anchor.body!r} in mechanism "
                        f"{mechanism.name!r}; bodies: {', '.join(mechanism.body_names)}"
                    )
                if not isinstance(anchor.point, Free):
                    raise InputError(f"{here}.{end}: a candidate's end is a box {{body, box: {{lower, upper}}}}")
                ends.append(
                    (anchor.body, (tuple(map(float, anchor.point.lower)), tuple(map(float, anchor.point.upper))))
                )
        else:
            raise InputError(
                f"{here}: expected [body_a, body_b] or {{a: {{body, box}}, b: {{body, box}}}}, got {record!r}"
            )
        (a, box_a), (b, box_b) = ends
        joints = (tree.joint_of[a], tree.joint_of[b])
        if joints[0] == joints[1]:
            raise InputError(f"{here}: {a!r} and {b!r} move as one body; a spring between them does nothing")
        key = tuple(sorted(joints))
        if key in seen:
            raise InputError(f"{here}: the same bodies as {where}[{seen[key]}] ({a!r} and {b!r} move with them)")
        seen[key] = i
        if joints[0] > joints[1]:
            (a, box_a), (b, box_b) = (b, box_b), (a, box_a)
        candidates.append(Candidate(a, b, box_a, box_b, tree.span(*sorted(joints))))
    return candidates
