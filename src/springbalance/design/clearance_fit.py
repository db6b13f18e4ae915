"""The loop that fits the springs to the arm: check, cut, solve again (see :mod:`springbalance.design.clearance`).

:func:`fit_to_arm` starts from the multi-start's optimum and returns the fitted solution, its
:class:`~springbalance.design.clearance.FitRecord` and the problem with the final linear rows (a copy:
the problem it is given is not changed).
"""

from __future__ import annotations

import time
from typing import Any, Iterable, Iterator, TypeAlias

import numpy as np

from springbalance.design.clearance import FIT_ROUNDS, Clearance, FitRecord, LinearRows, stacked_rows
from springbalance.design.clearance_distances import Pair, WorldEnds, pair_distances, placed_points
from springbalance.design.clearance_round import (
    INFEASIBLE_NOTE,
    INFEASIBLE_ROUNDS,
    OUTSIDE_NOTE,
    Tightening,
    fell_back,
    finished,
    solve_round,
)
from springbalance.design.clearance_rows import _ends_of, _mount_errors, _radius, _rows, mount_planes
from springbalance.design.mounts import MOUNT_ACCEPT
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution
from springbalance.model.collision import (
    DEFAULT_RADIUS,
    CollisionScene,
    Contact,
    capsule_contact,
    collision_geometry,
    placed_capsule,
)
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import Spring

#: Most poses per spring and object (and round) that join the watched set.
WORST_PER_PAIR = 4
#: Closest sampled poses per pair (a quarter of the joint box apart) from which :meth:`_Checker.descend` searches.
DESCENTS_PER_PAIR = 2
#: A pair is searched when its closest sampled pose is within this distance [m] of the margin.
DESCENT_BAND = 0.02
#: Most distance evaluations of one descent.
DESCENT_EVALUATIONS = 150

#: A contact watched: ``(*pair, pose set, sample)``.
Key: TypeAlias = tuple[str, str, "int | str", int, int, int]
#: World placements ``(rotation, translation)`` of a spring's end bodies.
Frames: TypeAlias = tuple[tuple[np.ndarray, np.ndarray], ...]
#: Per pair, its closest sampled poses ``(distance [m], pose set, sample)``.
Nearest: TypeAlias = dict[Pair, list[tuple[float, int, int]]]


class _Checker:
    """Distances of every two-point spring to the arm (and to each other) at a set of poses.

    Pose sets: 0 is the check set, 1 the 4× denser one, 2 the poses found by :meth:`descend`
    (local minima of a distance over the workspace's joint box, kept for the later rounds); further
    sets are those of :meth:`add_pose_set` (the verification's, :mod:`springbalance.design.verification`).
    """

    def __init__(self, problem: DesignProblem, clearance: Clearance):
        self.problem, self.clearance = problem, clearance
        mechanism = problem.mechanism
        self.scene = CollisionScene(mechanism, convex=True)
        base = problem.base_workspace
        self.bounds = [
            (float(np.min(base.joint_values[:, joint.index_v])), float(np.max(base.joint_values[:, joint.index_v])))
            for joint in mechanism.joints
        ]
        ranges = {joint.name: list(bound) for joint, bound in zip(mechanism.joints, self.bounds)}
        n = clearance.check_samples
        sampled = [
            Workspace.sobol(mechanism, n=n, ranges=ranges, seed=0).joint_values,
            Workspace.sobol(mechanism, n=4 * n, ranges=ranges, seed=1).joint_values,
        ]
        #: pose set 2 (grown by :meth:`descend`): its joint values and configurations
        self.found_joints: list[np.ndarray] = []
        self.found_poses: list[np.ndarray] = []
        self.joint_sets: list[np.ndarray | list[np.ndarray]] = [*sampled, self.found_joints]
        self.pose_sets: list[np.ndarray | list[np.ndarray]] = [mechanism.configurations(values) for values in sampled]
        self.pose_sets.append(self.found_poses)
        self.springs: list[Spring] = [spring for spring in problem.springs if getattr(spring, "ends", ()) == ("a", "b")]
        self.by_name = {_named(spring): spring for spring in self.springs}
        self.checked = {
            _named(spring): self.scene.indices_except([spring.anchors[e].body for e in _ends_of(spring)])
            for spring in self.springs
        }
        self._points: dict[bytes, dict[int, dict[str, tuple[np.ndarray, ...]]]] = {}  # (:meth:`body_points`)
        self.pose_placements: dict[int, tuple] = {}  # each pose set's (clearance_distances._pose_placements)
        self.frame_ids = {
            _named(spring): tuple(mechanism.frame_id(spring.anchors[e].body) for e in _ends_of(spring))
            for spring in self.springs
        }

    def add_pose_set(self, joint_values: np.ndarray) -> int:
        """Add the poses ``joint_values`` (M×nv) [rad or m] as a pose set; returns its index."""
        self.joint_sets.append(joint_values)
        self.pose_sets.append(self.problem.mechanism.configurations(joint_values))
        return len(self.pose_sets) - 1

    def _frames(self, spring: Spring) -> Frames:
        return tuple(
            (np.array(self.scene.frame(f).rotation), np.array(self.scene.frame(f).translation))
            for f in self.frame_ids[_named(spring)]
        )

    def _ends(self, spring: Spring, frames: Frames, x: np.ndarray, scenario: int) -> tuple[np.ndarray, np.ndarray]:
        """World points [m] of the two ends of ``spring``'s capsule (its body: :func:`_ends_of`)."""
        start, end = [
            placed_points(rotation, translation, point)
            for point, (rotation, translation) in zip(self.body_points(x, scenario)[_named(spring)], frames)
        ]
        return start, end

    def body_points(self, x: np.ndarray, scenario: int) -> dict[str, tuple[np.ndarray, ...]]:
        """Each spring's anchor points [m] in its bodies' frames at design ``x`` (in ``scenario``), once per design."""
        design = np.asarray(x, dtype=float).tobytes()
        if design not in self._points:
            self._points = {design: {}}  # the last design's only
        by_scenario = self._points[design]
        if scenario not in by_scenario:
            model = self.problem.model
            by_scenario[scenario] = {
                name: tuple(model.anchor_point(s, e, x, scenario) for e in _ends_of(s))
                for name, s in self.by_name.items()
            }
        return by_scenario[scenario]

    def _radii(self, x: np.ndarray) -> dict[str, float]:
        default = self.clearance.radius or DEFAULT_RADIUS
        return {_named(s): _radius(self.problem, s, x, default) for s in self.springs}

    def _pairs(self) -> Iterator[Pair]:
        """Every pair checked: ``(kind, spring, object index or other spring, scenario)``."""
        for scenario in range(self.problem.model.n_scenarios):
            for spring in self.springs:
                for index in self.checked[_named(spring)]:
                    yield ("object", _named(spring), index, scenario)
            if self.clearance.between_springs:
                for i, first in enumerate(self.springs):
                    for second in self.springs[i + 1 :]:
                        yield ("spring", _named(first), _named(second), scenario)

    def _contact(self, pair: Pair, x: np.ndarray, radius: dict[str, float]) -> tuple[Contact, Frames, Frames | None]:
        """Contact of ``pair`` at the placed pose, with the frames of its spring (and of the other spring)."""
        kind, first, second, scenario = pair
        spring = self.by_name[first]
        frames = self._frames(spring)
        ends = self._ends(spring, frames, x, scenario)
        if kind == "object":
            assert isinstance(second, int)  # an object pair names the object by its index
            return self.scene.capsule_distance(*ends, radius[first], second), frames, None
        assert isinstance(second, str)  # a spring pair names the other spring
        other = self.by_name[second]
        other_frames = self._frames(other)
        contact = capsule_contact(*ends, radius[first], *self._ends(other, other_frames, x, scenario), radius[second])
        return contact, frames, other_frames

    def measure(self, x: np.ndarray, pose_set: int) -> tuple[dict[Key, float], dict[str, float], Nearest]:
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
        if len(poses) and pairs:
            distances = pair_distances(self, pairs, x, radius, poses, self.clearance.margin + DESCENT_BAND)
        below: dict[Key, float] = {}
        closest = {_named(s): np.inf for s in self.springs}
        nearest: Nearest = {}
        for column, pair in enumerate(pairs):
            if not len(poses):
                break
            order = np.argsort(distances[:, column], kind="stable")
            nearest[pair] = [(float(distances[s, column]), pose_set, int(s)) for s in self._apart(pose_set, order)]
            for name in _names(pair):
                closest[name] = min(closest[name], float(distances[order[0], column]))
            for hit in np.flatnonzero(distances[:, column] < self.clearance.margin):
                below[pair + (pose_set, int(hit))] = float(distances[hit, column])
        return below, closest, nearest

    def placed_distances(
        self, pairs: list[Pair], x: np.ndarray, radius: dict[str, float], ends: WorldEnds
    ) -> list[float]:
        """The distance [m] of every pair at the placed pose: :meth:`_contact`'s, each spring's capsule built once
        for all its objects, from ``ends`` (its world ends there, :mod:`~springbalance.design.clearance_distances`)."""
        capsules: dict[tuple[str, int], tuple] = {}

        def placed(name: str, scenario: int) -> tuple:
            key = (name, scenario)
            if key not in capsules:
                start, end, length, centre, rotation = ends[key]
                capsules[key] = (start, end, placed_capsule(radius[name], length, centre, rotation))
            return capsules[key]

        values = []
        for kind, first, second, scenario in pairs:
            start, end, (shape, placement) = placed(first, scenario)
            if kind == "object":
                assert isinstance(second, int)  # an object pair names the object by its index
                values.append(self.scene.distance_to(shape, placement, second))
            else:
                assert isinstance(second, str)  # a spring pair names the other spring
                other_start, other_end, _ = placed(second, scenario)
                contact = capsule_contact(start, end, radius[first], other_start, other_end, radius[second])
                values.append(contact.distance)
        return values

    def _apart(self, pose_set: int, order: np.ndarray) -> list[int]:
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

    def descend(self, x: np.ndarray, nearest: Nearest) -> tuple[dict[Key, float], dict[str, float]]:
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
        below: dict[Key, float] = {}
        closest = {_named(s): np.inf for s in self.springs}

        def distance(values: np.ndarray, pair: Pair) -> float:
            self.scene.place(mechanism.configurations(values)[0])
            return self._contact(pair, x, radius)[0].distance

        for pair, starts in nearest.items():
            for start_distance, pose_set, sample in starts:
                if start_distance > self.clearance.margin + DESCENT_BAND:
                    continue
                start = np.asarray(self.joint_sets[pose_set][sample], dtype=float)
                found = minimize(
                    distance,
                    start,
                    args=(pair,),
                    method="L-BFGS-B",
                    bounds=self.bounds,
                    options={"eps": 1e-4, "maxfun": DESCENT_EVALUATIONS},
                )
                value = float(distance(found.x, pair))
                for name in _names(pair):
                    closest[name] = min(closest[name], value)
                if value < self.clearance.margin:
                    self.found_joints.append(np.array(found.x))
                    self.found_poses.append(mechanism.configurations(found.x)[0])
                    below[pair + (2, len(self.pose_sets[2]) - 1)] = value
        return below, closest

    def cuts(self, x: np.ndarray, keys: Iterable[Key]) -> tuple[list, list]:
        """The cuts of the watched ``keys`` at design ``x``."""
        clearance = self.clearance
        radius = self._radii(x)
        object_cuts: list = []
        spring_cuts: list = []
        for key in sorted(keys, key=lambda k: (k[4], k[5], k[:4])):
            pair, pose_set, sample = key[:4], key[4], key[5]
            kind, first, second, scenario = pair
            self.scene.place(self.pose_sets[pose_set][sample])
            contact, frames, other_frames = self._contact(pair, x, radius)
            spring = self.by_name[first]
            if kind == "object":
                assert isinstance(second, int)  # an object pair names the object by its index
                label = f"{first} clear of {self.scene.objects[second].name} (pose {pose_set}:{sample})"
                object_cuts.append((label, spring, scenario, frames, contact, radius[first], clearance.target))
            else:
                assert isinstance(second, str)  # a spring pair names the other spring
                spring_cuts.append(
                    (
                        f"{first} clear of {second} (pose {pose_set}:{sample})",
                        (spring, frames, radius[first]),
                        (self.by_name[second], other_frames, radius[second]),
                        scenario,
                        contact,
                        clearance.target,
                    )
                )
        return object_cuts, spring_cuts


def _named(spring: Spring) -> str:
    """The name of a problem's spring (a problem names every spring it is given)."""
    assert spring.name is not None
    return spring.name


def _names(pair: Pair) -> tuple[str, ...]:
    """The springs of ``pair``: its spring, and the other one of a spring pair."""
    kind, first, second, _ = pair
    if kind == "spring":
        assert isinstance(second, str)  # a spring pair names the other spring
        return (first, second)
    return (first,)


def _worst(below: dict[Key, float]) -> list[Key]:
    """Of the contacts below the margin, the :data:`WORST_PER_PAIR` closest per pair."""
    groups: dict[Pair, list[tuple[float, Key]]] = {}
    for key, distance in below.items():
        groups.setdefault(key[:4], []).append((distance, key))
    chosen: list[Key] = []
    for items in groups.values():
        chosen += [key for _, key in sorted(items)[:WORST_PER_PAIR]]
    return chosen


def _violations(checker: _Checker, x: np.ndarray) -> tuple[dict[Key, float], dict[str, float]]:
    """``(below, closest)`` at design ``x``: the poses where a spring comes closer than the margin, from the
    check set and the poses found before; when those are clear, from the 4× denser set; when that is clear
    too, from a descent between the samples. ``closest``: each spring's smallest distance found [m]."""
    below, closest, nearest = checker.measure(x, 0)
    if checker.pose_sets[2]:
        found, nearby, _ = checker.measure(x, 2)
        below.update(found)
        closest = {name: min(closest[name], nearby[name]) for name in closest}
    if not below:
        below, dense, nearest_dense = checker.measure(x, 1)
        closest = {name: min(closest[name], dense[name]) for name in closest}
        nearest = nearest_dense  # 4× denser: its closest poses are the better starts
    if not below:
        below, searched = checker.descend(x, nearest)
        closest = {name: min(closest[name], searched[name]) for name in closest}
    return below, closest


def fit_to_arm(
    problem: DesignProblem,
    solution: Solution,
    kept: LinearRows | None = None,
    trusted_first: bool = False,
    tighten: bool = False,
    checker: _Checker | None = None,
    **solve_options: Any,
) -> tuple[Solution, FitRecord, DesignProblem]:
    """Enforce the problem's clearance and mountings from ``solution`` (see the module documentation); each
    round's rows come after ``kept`` (rows found before: those of the ideal twin's fit, which the coils keep).
    ``checker``: the clearance's checker, with the poses found before in its pose set 2 (the verification's).

    When the rounds do not converge, the loop runs again from ``solution`` with a trust region in each round
    (:func:`~springbalance.design.clearance_round.trust_rows`), and keeps that fit when it converges; the
    record counts the rounds and time of both. ``trusted_first``: the run with the trust region comes first, and
    the one without it only when that does not converge (the ideal twin's fit: its springs' ``k·a·b`` family lets
    its rounds slide far; :mod:`springbalance.design.coil_start`).

    ``tighten``: once a round's design is fitted (clear, mounted, its rows met), rounds with the rows linearised
    again there follow while they lower the objective (:class:`~springbalance.design.clearance_round.Tightening`),
    and the fitted design of lowest objective is the fit's.

    ``solve_options`` go to :func:`~springbalance.design.solvers.solve_problem` (method, iterations).
    Returns the fitted solution, its :class:`FitRecord` and the problem with the last round's rows
    (``problem`` itself when no round ran).
    """
    clock = time.perf_counter()
    fitted = _fitted(problem, solution, kept, trusted_first, solve_options, tighten, checker)
    if fitted[1].converged or fitted[1].rounds == 0:
        return fitted
    retried = _fitted(problem, solution, kept, not trusted_first, solve_options, tighten, checker)
    chosen = retried if retried[1].converged else fitted
    chosen[1].rounds = fitted[1].rounds + retried[1].rounds
    chosen[1].seconds = time.perf_counter() - clock
    return chosen


def _fitted(
    problem: DesignProblem,
    solution: Solution,
    kept: LinearRows | None,
    trusted: bool,
    solve_options: dict[str, Any],
    tighten: bool = False,
    given: _Checker | None = None,
) -> tuple[Solution, FitRecord, DesignProblem]:
    """The loop of :func:`fit_to_arm`; ``trusted``: each round inside its trust region first; ``tighten``: the rounds
    of :class:`~springbalance.design.clearance_round.Tightening` after a fitted design; ``given``: its checker."""
    clock = time.perf_counter()
    clearance = problem.clearance
    x = np.array(solution.x, dtype=float)
    before = problem.objective_at(x)
    checker = given or (_Checker(problem, clearance) if clearance is not None else None)
    geometry = collision_geometry(problem.mechanism) if problem.mounts else None
    watched: set[Key] = set()
    planes = mount_planes(problem, np.asarray(problem.variables.start, dtype=float)) if problem.mounts else {}
    # stopped: rounds in a row that stopped infeasible, breaking a rule; outside: the last one stopped outside its rows
    rounds, converged, stopped, outside = 0, False, 0, False
    closest: dict[str, float] = {}
    mounts: dict[str, float] = {}
    limit = clearance.rounds if clearance is not None else FIT_ROUNDS
    tightening = Tightening()
    while True:
        mounts = _mount_errors(problem, x, geometry) if problem.mounts else {}
        mounted = all(error <= MOUNT_ACCEPT for error in mounts.values())
        if checker is not None:
            below, closest = _violations(checker, x)
            new = [key for key in _worst(below) if key not in watched]
            converged = not below and mounted
        else:
            new, converged = [], mounted
        if not stopped and not outside:  # x met its rows: the design to fall back to
            met = (x, solution, problem, closest, mounts, rounds)
        converged = converged and not stopped and not outside  # a design that broke its rows is no fit
        if converged and rounds and tighten:  # fitted: go on with the rows linearised here while the objective falls
            converged = not tightening.goes_on(problem.objective_at(x), met, rounds, limit)
        if converged or rounds >= limit or stopped >= INFEASIBLE_ROUNDS:
            break
        watched.update(new)
        object_cuts, spring_cuts = checker.cuts(x, watched) if checker is not None else ([], [])
        planes = mount_planes(problem, x, planes)
        problem = problem.with_linear_rows(stacked_rows(kept, _rows(problem, x, object_cuts, spring_cuts, planes)))
        resolved, note = solve_round(problem, x, solution, solve_options, trusted)
        if resolved is None:
            break
        stopped = stopped + 1 if note.startswith(INFEASIBLE_NOTE) else 0
        outside = note.startswith(OUTSIDE_NOTE)
        solution = resolved
        x = np.array(solution.x, dtype=float)
        rounds += 1
    if tightening.best is not None and (not converged or tightening.best[0] is not x):  # the best fitted design
        x, solution, problem, closest, mounts, converged = *tightening.best[:5], True
    elif stopped or outside:  # the last round broke its rows: back to the last design that met them (it is not clear)
        x, solution, problem, closest, mounts = fell_back(*met, note)
    poses = sum(len(poses) for poses in checker.pose_sets) if checker is not None else 0
    return finished(problem, solution, x, rounds, bool(converged), float(before), closest, mounts, poses, clock)
