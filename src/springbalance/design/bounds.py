"""Contradictions between a spring's bounds, found before solving.

A problem whose bounds contradict each other has no feasible design; the solver would only report
that no start found one. :func:`check_bounds` finds the contradictions that follow from the
bounds alone and names both keys:

- magnitudes no spring has, which would overflow the torques: an anchor region farther than
  :data:`MAX_DISTANCE` [m] from its body's origin, a parameter bound beyond :data:`MAX_PARAMETER`
  (SI units);

- ``min_length`` > ``max_length`` [m];
- a force floor above ``max_force`` [N]: ``|F| ≥ |force|`` of a constant-force element, ``F ≥
  initial_tension`` of an extension spring that keeps its tension, ``|F| ≥ preload`` of a
  compression or gas spring that stays compressed;
- lengths the anchor regions cannot reach: at every workspace sample the spring's length lies
  between the shortest and the longest distance of its two anchor regions (the longest exactly,
  from the regions' corners; the shortest from below, from their centres and radii), so

  - ``max_length`` below the shortest distance at some sample, or ``min_length`` above the
    longest distance at some sample, is impossible;
  - the free lengths that the spring's length options allow (``keep_tension``, ``max_stretch``,
    ``stays_compressed``, ``stroke``: :meth:`free_length_interval` of its law) must meet the
    ``free_length`` bounds.

A routed spring (over pulleys) gets one check of its own, :func:`check_cable` (which
:class:`~springbalance.design.problem.DesignProblem` runs for every routed spring): its path can
be no longer than the sum of its segments' longest distances (plus ``2π r`` per wrapping pulley),
so a shortest cable at least that long leaves the spring slack everywhere. Its other length
bounds, and anchors mounted ``on: collision`` without a box, are left to the solver. Lengths in m,
forces in N.
"""

from __future__ import annotations

import itertools
from typing import Iterable, Protocol, Sequence

import numpy as np

from springbalance.errors import InputError
from springbalance.model.kinematics import StackedKinematics, WorkspaceKinematics
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import Spring, TwoPointSpring
from springbalance.springs.params import Region

#: slack of the checks [m or N] relative to the compared values, plus the same absolute amount
TOLERANCE = 1e-9
#: the farthest an anchor region may lie from its body's origin [m]
MAX_DISTANCE = 1e3
#: the largest magnitude of a parameter bound (SI units: N/m, m, N, ...)
MAX_PARAMETER = 1e12
#: the options that bound the free length through the spring's length
_LENGTH_OPTIONS = ("keep_tension", "max_stretch", "stays_compressed", "stroke")


class _Problem(Protocol):
    """What the checks read of a :class:`~springbalance.design.problem.DesignProblem` (which imports this module)."""

    @property
    def springs(self) -> Sequence[Spring]: ...

    @property
    def base_workspace(self) -> Workspace: ...


def check_magnitudes(springs: Iterable[Spring]) -> None:
    """Raise :class:`InputError` for an anchor region beyond :data:`MAX_DISTANCE` or a parameter bound
    beyond :data:`MAX_PARAMETER` (see the module documentation)."""
    for spring in springs:
        _check_magnitudes(spring, f"spring {spring.name!r}")


def check_bounds(problem: _Problem) -> None:
    """Raise :class:`InputError` at the first contradiction between the bounds of ``problem``'s springs."""
    for spring in problem.springs:
        label = f"spring {spring.name!r}"
        _check_magnitudes(spring, label)
        _check_lengths(spring, label)
        _check_force(spring, label)
    kinematics: WorkspaceKinematics | StackedKinematics | None = None
    for spring in problem.springs:
        if tuple(spring.anchors) != ("a", "b") or getattr(spring, "via", None):
            continue
        try:
            regions = [spring.anchors[end].region() for end in ("a", "b")]
        except InputError:  # mounted on collision geometry without a box: no region before solving
            continue
        if kinematics is None:
            kinematics = problem.base_workspace.kinematics()
        shortest, longest = _distance_bounds(kinematics, [spring.anchors[end].body for end in ("a", "b")], regions)
        _check_reach(spring, f"spring {spring.name!r}", shortest, longest)


def _bounds(spring: Spring, key: str) -> tuple[float, float] | None:
    """``(lower, upper)`` of parameter ``key`` (equal for a fixed value), or None without it."""
    value = getattr(spring, "parameters", {}).get(key)
    if value is None:
        return None
    if hasattr(value, "lower"):
        return float(np.min(value.lower)), float(np.max(value.upper))
    return float(value), float(value)


def _check_magnitudes(spring: Spring, label: str) -> None:
    for key in getattr(spring, "parameters", {}):
        bounds = _bounds(spring, key)
        if bounds is not None and max(abs(bounds[0]), abs(bounds[1])) > MAX_PARAMETER:
            raise InputError(
                f"{label}: {key} bound {max(bounds, key=abs):g} is beyond ±{MAX_PARAMETER:g} (SI units); "
                "no spring has it, and the torques would overflow"
            )
    for end, anchor in spring.anchors.items():
        try:
            region = anchor.region()
        except InputError:
            continue
        corners = (
            [region.offset]
            if not region.basis.shape[1]
            else [region.point(np.array(choice)) for choice in itertools.product(*zip(region.lower, region.upper))]
        )
        reach = float(max(np.max(np.abs(corner)) for corner in corners))  # a coordinate (no overflow)
        if not reach <= MAX_DISTANCE:
            raise InputError(
                f"{label}: anchor {end} has a coordinate of {reach:.4g} m in the frame of {anchor.body!r}; "
                f"an anchor lies within {MAX_DISTANCE:g} m of its body's origin"
            )


def _exceeds(value: float, limit: float) -> bool:
    return value > limit + TOLERANCE * (1.0 + abs(limit))


def _check_lengths(spring: Spring, label: str) -> None:
    low, high = getattr(spring, "min_length", None), getattr(spring, "max_length", None)
    if low is not None and high is not None and _exceeds(low, high):
        raise InputError(f"{label}: min_length {low:g} m > max_length {high:g} m; no length meets both")


def _check_force(spring: Spring, label: str) -> None:
    limit = getattr(spring, "max_force", None)
    if limit is None:
        return
    floors: list[tuple[str, float, str]] = []
    force = _bounds(spring, "force")
    if force is not None and getattr(spring, "kind", None) == "constant_force":
        lower, upper = force
        floors.append(("force", 0.0 if lower <= 0 <= upper else min(abs(lower), abs(upper)), "|F| = |force|"))
    tension = _bounds(spring, "initial_tension")
    if tension is not None and getattr(spring, "keep_tension", False):
        floors.append(("initial_tension", tension[0], "with keep_tension, F ≥ initial_tension"))
    preload = _bounds(spring, "preload")
    if preload is not None and getattr(spring, "stays_compressed", False):
        floors.append(("preload", preload[0], "with stays_compressed, |F| ≥ preload"))
    for key, floor, why in floors:
        if _exceeds(floor, limit):
            raise InputError(
                f"{label}: {key} is at least {floor:g} N, above max_force {limit:g} N ({why} at every "
                "sample); no force meets both"
            )


def check_cable(problem: _Problem, spring: TwoPointSpring) -> None:
    """Refuse a routed ``spring`` whose shortest allowed cable is at least the longest path it can make."""
    cable = _bounds(spring, "cable_length")
    if cable is None:
        return
    anchors = list(spring.anchors.values())
    kinematics = problem.base_workspace.kinematics()
    longest: float | np.ndarray = 2 * np.pi * sum(spring.radii)  # what wrapping pulleys can add [m]
    for first, second in zip(anchors, anchors[1:]):
        longest = (
            longest + _distance_bounds(kinematics, [first.body, second.body], [first.region(), second.region()])[1]
        )
    reach = float(np.max(longest))
    if cable[0] >= reach:
        raise InputError(
            f"spring {spring.name!r}: its cable ({cable[0]:.6g} m at the shortest) is at least as long "
            f"as its path can ever be ({reach:.6g} m over the workspace): the spring would be slack "
            "everywhere; shorten cable_length"
        )


def _distance_bounds(
    kinematics: WorkspaceKinematics | StackedKinematics, bodies: Sequence[str], regions: Sequence[Region]
) -> tuple[np.ndarray, np.ndarray]:
    """Per sample, a lower bound of the shortest and the longest distance [m] between two anchor regions."""
    corners: list[np.ndarray] = []
    centres: list[np.ndarray] = []
    radii: list[float] = []
    for body, region in zip(bodies, regions):
        local = (
            np.array([region.point(np.array(choice)) for choice in itertools.product(*zip(region.lower, region.upper))])
            if region.basis.shape[1]
            else region.offset[None, :]
        )
        placement = kinematics.body(body)
        world = np.stack([placement.points(point) for point in local], axis=1)  # N × corners × 3
        centre = local.mean(axis=0)
        corners.append(world)
        centres.append(placement.points(centre))
        radii.append(float(np.max(np.linalg.norm(local - centre, axis=1))))
    # the longest distance is between two corners: one corner of the first region at a time keeps the
    # temporaries at N × corners × 3 (all pairs at once took 1.5 KiB per sample and more in its norms)
    longest = np.zeros(corners[0].shape[0])
    for corner in range(corners[0].shape[1]):
        differences = corners[0][:, corner, None, :] - corners[1]  # N × corners × 3 [m]
        longest = np.maximum(longest, np.max(np.linalg.norm(differences, axis=-1), axis=1))
    shortest = np.maximum(np.linalg.norm(centres[0] - centres[1], axis=1) - radii[0] - radii[1], 0.0)
    return shortest, longest


def _check_reach(spring: Spring, label: str, shortest: np.ndarray, longest: np.ndarray) -> None:
    high = getattr(spring, "max_length", None)
    if high is not None and _exceeds(float(np.max(shortest)), high):
        sample = int(np.argmax(shortest))
        raise InputError(
            f"{label}: max_length {high:g} m, but its anchor regions are at least {shortest[sample]:.4g} m "
            f"apart at workspace sample {sample}"
        )
    low = getattr(spring, "min_length", None)
    if low is not None and _exceeds(low, float(np.min(longest))):
        sample = int(np.argmin(longest))
        raise InputError(
            f"{label}: min_length {low:g} m, but its anchor regions are at most {longest[sample]:.4g} m "
            f"apart at workspace sample {sample}"
        )
    free_length = _bounds(spring, "free_length")
    interval = getattr(spring, "free_length_interval", None)
    options = [key for key in _LENGTH_OPTIONS if getattr(spring, key, None) not in (None, False)]
    if free_length is None or interval is None or not options:
        return
    low, _ = interval(shortest)  # the options' lower bounds grow with the lengths: the shortest ones bound them
    _, high = interval(longest)  # and their upper bounds: the longest ones
    given = f"free_length [{free_length[0]:g}, {free_length[1]:g}] m"
    if _exceeds(low, high):
        raise InputError(
            f"{label}: {', '.join(options)} ask for a free length from {low:.4g} m up to {high:.4g} m, "
            "which is empty: the anchor regions span too wide a range of lengths over the workspace"
        )
    if _exceeds(free_length[0], high) or _exceeds(low, free_length[1]):
        reach = f"at most {high:.4g} m" if _exceeds(free_length[0], high) else f"at least {low:.4g} m"
        raise InputError(
            f"{label}: {given}, but with {' and '.join(options)} the anchor regions allow a free length of {reach} only"
        )
