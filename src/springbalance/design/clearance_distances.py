"""The clearance fit's distances at many poses, coal asked only where a cheap lower bound cannot decide.

A spring is a capsule (segment ``A–B``, radius ``r``); every collision object lies inside a capsule of its own
(:meth:`~springbalance.model.collision.CollisionScene.bounding_capsules`: axis ``S–E``, radius ``ρ``). So the
distance of the spring to the object is at least

.. math:: \\underline{d} = \\operatorname{dist}(A\\!-\\!B,\\ S\\!-\\!E) - r - ρ ,

and between two springs the segments' distance less both radii (which is their distance). These bounds take
one pass of array operations over all poses and pairs (:func:`~springbalance.model.collision.segment_distances`).
coal's exact signed distance is asked only where the bound is within ``threshold`` [m] (the fit's margin and its
descent band: where a distance can matter), and, per pair, at the poses of lowest bound until the bound exceeds
the least distance found, so that each pair's least distance is coal's own. The other entries keep their bound,
above ``threshold`` and above their pair's least distance: every use of the distances (those below the margin,
each spring's closest, the closest poses within the descent band) sees the values coal gives, bit for bit.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Protocol, TypeAlias

import numpy as np

from springbalance.design.problem import DesignProblem
from springbalance.model.collision import CollisionScene, capsule_placements, segment_distances
from springbalance.springs.laws import Spring

#: A pair checked: ``(kind, spring, object index or other spring, scenario)``, kind ``"object"`` or ``"spring"``.
Pair: TypeAlias = tuple[str, str, "int | str", int]
#: Each spring's capsule at one pose: ``(spring, scenario) → (start, end, length, centre, rotation)``, its world ends
#: [m] and :func:`~springbalance.model.collision.capsule_placements`' placement.
WorldEnds: TypeAlias = Mapping[tuple[str, int], tuple]


class Checker(Protocol):
    """What the distances need of the clearance fit's checker (:class:`~springbalance.design.clearance_fit._Checker`)."""

    problem: DesignProblem
    scene: CollisionScene
    by_name: dict[str, Spring]
    frame_ids: dict[str, tuple[int, ...]]
    #: what :func:`_pose_placements` keeps: ``id(poses) → (poses, len(poses), placements)``
    pose_placements: dict[int, tuple]

    def body_points(self, x: np.ndarray, scenario: int) -> dict[str, tuple[np.ndarray, ...]]:
        """Each spring's anchor points [m] in its end bodies' frames at design ``x`` (in ``scenario``)."""
        ...

    def placed_distances(
        self, pairs: list[Pair], x: np.ndarray, radius: dict[str, float], ends: WorldEnds
    ) -> list[float]:
        """coal's distance [m] of every pair at the pose the scene is placed at (``ends``: the springs' capsules
        there)."""
        ...


#: Configurations (Pinocchio's order): an array (poses × nq) or a list of them.
Poses: TypeAlias = "np.ndarray | list[np.ndarray]"

#: Round-off allowance [m] of the bounds against coal's distances (GJK's tolerance is far below it).
BOUND_SLACK = 1e-6


def pair_distances(
    checker: Checker,
    pairs: list[Pair],
    x: np.ndarray,
    radius: dict[str, float],
    poses: Poses,
    threshold: float,
) -> np.ndarray:
    """Distances [m] (poses × pairs) of every pair at the configurations ``poses`` (see the module docstring):
    coal's where the bound is within ``threshold`` and at each pair's least, the bound elsewhere."""
    bounds, ends = _bounds(checker, pairs, x, radius, poses)
    distances = bounds.copy()
    exact = bounds <= threshold + BOUND_SLACK
    # a pair with no bound within the threshold: coal's at its pose of lowest bound, an upper bound u of its least
    lacking = np.flatnonzero(~exact.any(axis=0))
    exact[np.argmin(bounds[:, lacking], axis=0), lacking] = True
    _fill(checker, pairs, x, radius, poses, distances, exact, ends)
    # then coal's at every pose whose bound is within the least found, at once
    least = np.min(np.where(exact, distances, np.inf), axis=0)
    _fill(checker, pairs, x, radius, poses, distances, ~exact & (bounds <= least[None, :] + BOUND_SLACK), ends)
    return distances


def placed_points(rotations: np.ndarray, translations: np.ndarray, point: np.ndarray) -> np.ndarray:
    """``R p + t`` [m] at every pose (rotations poses × 3 × 3, translations poses × 3; or one pose, 3 × 3 and 3),
    summed column by column, ``R[:, 0] p₀ + R[:, 1] p₁ + R[:, 2] p₂``, each product and sum rounded on its own. The
    cuts take one pose's ends with it too (:meth:`~springbalance.design.clearance_fit._Checker._ends`), so both
    agree bit for bit whatever NumPy's own kernels do: NumPy 2.4's ``R @ p`` and an ``einsum`` differ from it in the
    last bits (on 8,192 UR5 poses, 3,790 of 24,576 coordinates for the ``einsum``)."""
    return rotations[..., 0] * point[0] + rotations[..., 1] * point[1] + rotations[..., 2] * point[2] + translations


def _fill(
    checker: Checker,
    pairs: list[Pair],
    x: np.ndarray,
    radius: dict[str, float],
    poses: Poses,
    distances: np.ndarray,
    wanted: np.ndarray,
    capsules: dict[tuple[str, int], tuple[np.ndarray, ...]],
) -> None:
    """Write coal's distance into ``distances`` wherever ``wanted`` (poses × pairs) is set, pose by pose;
    ``capsules``: each spring's :data:`WorldEnds` entry at every pose (arrays over the poses)."""
    for sample in np.flatnonzero(wanted.any(axis=1)):
        columns = np.flatnonzero(wanted[sample])
        checker.scene.place(poses[int(sample)])
        placed = _AtPose(capsules, int(sample))
        distances[sample, columns] = checker.placed_distances([pairs[c] for c in columns], x, radius, placed)


class _AtPose(Mapping):
    """The :data:`WorldEnds` of one pose, each spring's taken from the arrays over the poses when it is asked for."""

    def __init__(self, capsules: dict[tuple[str, int], tuple[np.ndarray, ...]], sample: int) -> None:
        self.capsules, self.sample = capsules, sample

    def __getitem__(self, key: tuple[str, int]) -> tuple:
        return tuple(array[self.sample] for array in self.capsules[key])

    def __iter__(self) -> Iterator[tuple[str, int]]:
        return iter(self.capsules)

    def __len__(self) -> int:
        return len(self.capsules)


#: What a pose set's placements are, whatever the design: its spring frames' rotations (poses × frames × 3 × 3) and
#: translations, each frame's index there, and the objects' bounding capsules' axes (poses × objects × 3, both ends)
#: and radii.
PosePlacements: TypeAlias = tuple[np.ndarray, np.ndarray, dict[int, int], np.ndarray, np.ndarray, np.ndarray]


def _pose_placements(checker: Checker, poses: Poses) -> PosePlacements:
    """The placements of ``poses`` that do not depend on the design (:data:`PosePlacements`), computed once per
    pose set and kept in ``checker.pose_placements`` (by the pose set's identity and size: the descent's set grows):
    every round of a fit checks the same poses, and their kinematics were two fifths of the check's time."""
    key = id(poses)
    kept = checker.pose_placements.get(key)
    if kept is not None and kept[0] is poses and kept[1] == len(poses):
        return kept[2]
    scene = checker.scene
    frames = sorted({frame for ids in checker.frame_ids.values() for frame in ids})
    where = {frame: index for index, frame in enumerate(frames)}
    n = len(poses)
    frame_rotations, frame_translations = np.empty((n, len(frames), 3, 3)), np.empty((n, len(frames), 3))
    object_rotations, object_translations = (
        np.empty((n, len(scene.objects), 3, 3)),
        np.empty((n, len(scene.objects), 3)),
    )
    for sample, q in enumerate(poses):
        scene.move(q)
        object_rotations[sample], object_translations[sample] = scene.object_placements()
        for index, frame in enumerate(frames):
            placement = scene.frame(frame)
            frame_rotations[sample, index], frame_translations[sample, index] = (
                placement.rotation,
                placement.translation,
            )
    starts, ends, widths = scene.bounding_capsules()
    object_start = np.einsum("poij,oj->poi", object_rotations, starts) + object_translations
    object_end = np.einsum("poij,oj->poi", object_rotations, ends) + object_translations
    placements = (frame_rotations, frame_translations, where, object_start, object_end, widths)
    checker.pose_placements[key] = (poses, len(poses), placements)
    return placements


def _bounds(
    checker: Checker, pairs: list[Pair], x: np.ndarray, radius: dict[str, float], poses: Poses
) -> tuple[np.ndarray, dict[tuple[str, int], tuple[np.ndarray, ...]]]:
    """Lower bounds [m] of every pair's distance at every pose (poses × pairs), and each spring's capsule at every
    pose (:data:`WorldEnds`' entries as arrays over the poses: ends from :func:`placed_points`) for coal's."""
    frame_rotations, frame_translations, where, object_start, object_end, widths = _pose_placements(checker, poses)
    n = len(poses)
    placed: dict[tuple[str, int], tuple[np.ndarray, ...]] = {}

    def segment(name: str, scenario: int) -> tuple[np.ndarray, np.ndarray]:
        """The spring's two ends (world, poses × 3) in ``scenario``."""
        if (name, scenario) not in placed:
            start, end = (
                placed_points(frame_rotations[:, where[frame]], frame_translations[:, where[frame]], body_point)
                for body_point, frame in zip(checker.body_points(x, scenario)[name], checker.frame_ids[name])
            )
            placed[name, scenario] = (start, end, *capsule_placements(start, end))
        return placed[name, scenario][0], placed[name, scenario][1]

    bounds = np.empty((n, len(pairs)))
    for column, (kind, first, second, scenario) in enumerate(pairs):
        start, end = segment(first, scenario)
        if kind == "object":
            assert isinstance(second, int)  # an object pair names the object by its index
            gap = segment_distances(start, end, object_start[:, second], object_end[:, second])
            bounds[:, column] = gap - radius[first] - widths[second]
        else:
            assert isinstance(second, str)  # a spring pair names the other spring
            gap = segment_distances(start, end, *segment(second, scenario))
            bounds[:, column] = gap - radius[first] - radius[second]
    return bounds, placed
