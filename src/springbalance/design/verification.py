r"""Verification of a design at poses it was not optimised on (docs/model.md, "Verification").

A design is optimised on ``N`` workspace samples: its rules (the springs' constraint rows: stresses,
hooks, tension, solid length, buckling, ``no_joint_worse``) hold there, and nothing says they hold
between them. :func:`check_design` evaluates the same rows at ``M = 10 N`` poses the design has not
seen (:func:`verification_poses`):

- a workspace drawn over a box of joint ranges (``sobol``, ``random``, ``grid``): ``M`` scrambled Sobol
  points of the same box with its couplings, seed :data:`VERIFY_SEED` (+ the round; 100 more when that
  is the workspace's own seed); a grid's joint held at one value stays there;
- any other ordered workspace (a path: a sweep, a trajectory): ``⌈M/(N-1)⌉`` points on every segment
  between consecutive poses, at fractions ``(k + φ)/m`` with ``φ ∈ (0, 1)`` another offset each round
  (never a sample itself);
- an unordered array of poses: Sobol points of the box of its smallest and largest joint values.

Per rule it reports the smallest margin ``c_i(x) + ρ`` over the poses, where ``c_i`` is the row and ``ρ``
the reserve the optimisation keeps (a coil's :data:`~springbalance.springs.laws.coil.STRESS_RESERVE` of each
allowable stress): the rule itself is checked, the reserve being there for exactly these poses. Rows that
do not depend on the pose (a coil's index, its initial tension) are left out, but for a coil's fatigue damage
rows, which are judged over the coil's force range at the poses (:mod:`~springbalance.design.verification_fatigue`).
It reports the residual
torque's peak and RMS per joint over the poses beside those over the samples; with a peak objective
(``peak``, ``joint_peaks``, ``peak_then_joints``) the residual fails when the objective over the poses
exceeds its value over the samples by more than :data:`PEAK_EXCESS` (an RMS or a potential objective
is an average, which a denser sampling estimates, not a bound: reported only). With a
:class:`~springbalance.design.clearance.Clearance`, every spring's distance to the arm is checked at the
same poses (the fit's own check sets use other seeds).

A coil's length rule ``L ≥ l0`` binds, for most layouts, on the boundary of the joint box (a joint at its
limit), which Sobol points approach but never reach, and so does its largest force (its body stress; the hooks'
stresses and the fatigue ceiling grow with the same force, a compression coil's solid length binds at the same
length). For a box workspace, the worst poses of a helical coil's length rule and body stress
(:func:`~springbalance.design.verification_refine.searched`) are therefore searched to its least margin inside the box (:mod:`~springbalance.design.verification_refine`), and
every rule is judged at those poses too; the residual torque is judged at the Sobol poses only (the searched
poses are chosen for a rule and would bias its statistics).

The check names the poses to add as samples when a rule fails (the :data:`WORST_PER_RULE` worst per rule,
and for a failed peak the worst per joint), and the clearance contacts below the margin;
:mod:`springbalance.design.verification_loop` re-solves with them. A length rule without a reserve (an ideal
spring's ``L ≥ l0``), not searched to judge it, is searched from its failing poses when it fails, and the poses
found join the samples too (:func:`_searched`): a re-solve then holds it at its least margin, not at
Sobol poses near it, where it would fail again a little further on (the Panda with four ideal springs at seed 1:
1.86 mm slack after three re-solves, with the elbow 0.8° inside its range's end).
"""

from __future__ import annotations

import copy
import dataclasses
import time

import numpy as np

from springbalance.design.clearance_fit import Key, _Checker, _worst
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import FEASIBILITY_TOLERANCE
from springbalance.design.torque_model.variables import ConstraintBlock
from springbalance.design.verification_fatigue import damage_rule, is_damage_block, widened_bounds
from springbalance.design.verification_record import JointResidual, RuleMargin, VerificationRecord
from springbalance.design.verification_refine import (
    RULES,
    evaluated_at,
    refined_poses,
    search_box,
    search_starts,
    searched,
)
from springbalance.model.workspace import Coupling, Workspace

#: the poses verified per sample optimised on
VERIFY_FACTOR = 10
#: seed of the Sobol poses of the first round (each later round adds one)
VERIFY_SEED = 27
#: with a peak objective, the residual fails when its value over the poses verified exceeds its
#: value over the samples by more than this fraction [1]
PEAK_EXCESS = 0.05
#: most poses per failed rule (and per joint of a failed peak) that join the samples in a round
WORST_PER_RULE = 4
#: poses evaluated at once (the memory of one block of kinematics and rows)
CHUNK = 8192
#: the objectives whose residual is a bound the verification checks
PEAK_OBJECTIVES = ("peak", "joint_peaks", "peak_then_joints")
#: the golden ratio's fractional part: the offsets of the path points in successive rounds
_GOLDEN = 0.6180339887498949


def verification_poses(workspace: Workspace, round_: int = 0, factor: int = VERIFY_FACTOR) -> tuple[np.ndarray, str]:
    """``(joint values (M×nv) [rad or m], how they were drawn)``: ``M ≥ factor · N`` poses of ``workspace``'s
    region that are none of its samples (see the module documentation); ``round_`` draws another set."""
    count = factor * workspace.size
    description = workspace.description
    mechanism = workspace.mechanism
    if "lower" in description and "upper" in description:
        lower, upper = np.array(description["lower"], dtype=float), np.array(description["upper"], dtype=float)
        if description.get("kind") == "grid" and isinstance(description.get("n"), list):
            held = np.array(description["n"]) == 1  # a joint the grid holds at its range's midpoint
            lower[held] = upper[held] = (lower[held] + upper[held]) / 2
        couplings = [Coupling(**record) for record in description.get("couplings", [])]
        where = "the workspace's joint ranges"
    elif workspace.ordered and workspace.size > 1:
        return _along_path(workspace.joint_values, count, round_), "interpolated between the path's poses"
    else:
        lower, upper = workspace.joint_values.min(axis=0), workspace.joint_values.max(axis=0)
        couplings, where = [], "the box of the workspace's samples"
    seed = VERIFY_SEED + round_
    if description.get("seed") == seed:
        seed += 100
    ranges = {joint.name: [lower[joint.index_v], upper[joint.index_v]] for joint in mechanism.joints}
    values = Workspace.sobol(mechanism, n=count, ranges=ranges, couplings=couplings, seed=seed).joint_values
    return values, f"Sobol seed {seed} over {where}"


def _along_path(values: np.ndarray, count: int, round_: int) -> np.ndarray:
    """``m = ⌈count/(N-1)⌉`` points on each segment of the path ``values`` (N×nv), at fractions ``(k + φ)/m``."""
    per_segment = int(np.ceil(count / (values.shape[0] - 1)))
    offset = (0.5 + round_ * _GOLDEN) % 1.0  # in (0, 1): never a pose of the path itself
    fractions = (np.arange(per_segment) + offset) / per_segment
    starts, steps = values[:-1], np.diff(values, axis=0)
    return (starts[:, None, :] + fractions[None, :, None] * steps[:, None, :]).reshape(-1, values.shape[1])


@dataclasses.dataclass
class Check:
    """One verification of a design.

    Attributes:
        record: what it found (without rounds, added poses and time: the loop fills them in).
        poses: joint values (k×nv) [rad or m] to add as samples (the worst of every failed rule).
        contacts: the clearance contacts below the margin to cut (keys of the fit's checker).
    """

    record: VerificationRecord
    poses: np.ndarray
    contacts: list[Key]


class _Dense:
    """The rows and torques of design ``x`` at poses, chunk by chunk: per rule its worst candidates."""

    def __init__(self, problem: DesignProblem, x: np.ndarray, values: np.ndarray) -> None:
        self.problem, self.x, self.values = problem, x, values
        self.blocks = [block for block in problem.model.constraint_blocks if block.per_sample]
        #: per block, its :data:`WORST_PER_RULE` smallest margins per chunk: (margin, pose, scenario)
        self.candidates: dict[int, list[tuple[float, int, int]]] = {block.offset: [] for block in self.blocks}
        #: the blocks of the rules searched to the box's boundary, and their margins at every pose (M × k)
        self.searched_blocks = [block for block in self.blocks if searched(block)]
        taus, potentials, self.searched_margins = self._evaluate(values, 0)
        #: the residual torque (M·S × nv) and potential (M·S), in scenario blocks as the problem's samples
        self.tau = np.vstack([np.vstack(parts) for parts in taus])
        self.potential = np.concatenate([np.concatenate(parts) for parts in potentials])

    def _evaluate(
        self, values: np.ndarray, first: int
    ) -> tuple[list[list[np.ndarray]], list[list[np.ndarray]], np.ndarray]:
        """Evaluate the design at ``values`` (poses numbered from ``first``): add each block's worst candidates;
        return the torques and potentials per scenario (lists of chunks) and the searched rules' margins."""
        problem, model = self.problem, self.problem.model
        scenarios = model.n_scenarios
        taus: list[list[np.ndarray]] = [[] for _ in range(scenarios)]
        potentials: list[list[np.ndarray]] = [[] for _ in range(scenarios)]
        searched = []
        for start in range(0, values.shape[0], CHUNK):
            part = values[start : start + CHUNK]
            tau, potential, rows = evaluated_at(problem, self.x, part)
            m = part.shape[0]
            for scenario in range(scenarios):
                taus[scenario].append(tau[scenario * m : (scenario + 1) * m])
                potentials[scenario].append(potential[scenario * m : (scenario + 1) * m])
            for block in self.blocks:
                margins = rows[:, block.offset] + block.reserve
                for i in np.argsort(margins, kind="stable")[:WORST_PER_RULE]:
                    self.candidates[block.offset].append((float(margins[i]), first + start + int(i) % m, int(i) // m))
            offsets, reserves = [b.offset for b in self.searched_blocks], [b.reserve for b in self.searched_blocks]
            searched.append((rows[:, offsets] + np.array(reserves)).reshape(scenarios, m, len(offsets)).min(axis=0))
        return taus, potentials, np.vstack(searched) if searched else np.empty((0, len(self.searched_blocks)))

    def extended(self, poses: np.ndarray) -> _Dense:
        """These poses and ``poses`` (k×nv) for the rules: the candidates of both (``tau`` and ``potential`` stay
        this one's: the residual is judged at these poses only)."""
        other = copy.copy(self)
        other.candidates = {offset: list(found) for offset, found in self.candidates.items()}
        other.values = np.vstack([self.values, poses])
        other._evaluate(poses, self.values.shape[0])
        return other

    def pose(self, index: int) -> dict[str, float]:
        return {joint.name: float(self.values[index, joint.index_v]) for joint in self.problem.mechanism.joints}

    def scenario(self, index: int) -> str | None:
        return self.problem.scenarios[index].name if self.problem.scenarios else None

    def rule(self, block: ConstraintBlock, sampled_rows: np.ndarray) -> tuple[RuleMargin, list[int]]:
        """The rule of ``block``: its worst margin here and over the samples; the worst failing poses."""
        candidates = sorted(self.candidates[block.offset])
        margin, pose, scenario = candidates[0]
        sampled = float(np.min(sampled_rows[:, block.offset])) + block.reserve
        passed = margin >= -FEASIBILITY_TOLERANCE
        rule = RuleMargin(
            block.spring or "",
            block.name,
            block.unit,
            margin,
            sampled,
            self.pose(pose),
            self.scenario(scenario),
            passed,
        )
        failing = list(dict.fromkeys(p for value, p, _ in candidates if value < -FEASIBILITY_TOLERANCE))
        return rule, failing[:WORST_PER_RULE]


def _searched(
    problem: DesignProblem,
    dense: _Dense,
    x: np.ndarray,
    blocks: list[ConstraintBlock],
    at: np.ndarray | None = None,
) -> np.ndarray:
    """The worst poses of each rule of ``blocks``, searched from the poses verified to its least margin within the
    workspace's box (:mod:`~springbalance.design.verification_refine`; ``at``: the rules' margins at those poses,
    when known); none for another workspace."""
    box = search_box(problem.base_workspace) if blocks else None
    if box is None:
        return np.empty((0, problem.mechanism.nv))
    return refined_poses(problem, x, search_starts(problem, x, dense.values, box, blocks, at), box)


def check_design(
    problem: DesignProblem, x: np.ndarray, round_: int = 0, checker: _Checker | None = None, mode: str = "resolve"
) -> Check:
    """Verify design ``x`` of ``problem`` at the poses of round ``round_`` (see the module documentation).

    ``checker``: the clearance checker of the problem (with a clearance); the poses join it as a pose set.
    """
    clock = time.perf_counter()
    values, sampling = verification_poses(problem.base_workspace, round_)
    x = np.asarray(x, dtype=float)
    unseen = dense = _Dense(problem, x, values)
    found = _searched(problem, unseen, x, unseen.searched_blocks, unseen.searched_margins)
    if found.size:  # the searched rules' worst poses: for the rules only, not the residual
        dense = unseen.extended(found)
        sampling += f", and {found.shape[0]} pose(s) searched to a rule's least margin"
    widened = widened_bounds(problem, dense, x)  # a coil's fatigue bounds at its force range there
    if widened is not None:
        x = widened
    sampled = problem.evaluate(x)
    rules, poses, unsearched = [], [], []
    for block in problem.model.constraint_blocks:
        if block.per_sample:
            rule, failing = dense.rule(block, sampled.constraint_rows)
            if not rule.passed and block.name in RULES and not searched(block):  # (no reserve: judged unsearched)
                unsearched.append(block)
        elif is_damage_block(block):
            rule, failing = damage_rule(problem, dense, block, x, sampled.constraint_rows, WORST_PER_RULE)
        else:
            continue
        rules.append(rule)
        poses += failing
    residual, objective, peak_poses = _residual(problem, unseen, sampled.tau, sampled.potential)
    poses += peak_poses
    contacts: list[Key] = []
    if checker is not None:
        clearance_rules, contacts = _clearance(checker, dense, x)
        rules += clearance_rules
    residual_checked = problem.objective.name in PEAK_OBJECTIVES
    residual_passed = not peak_poses
    record = VerificationRecord(
        poses=int(values.shape[0]),
        sampling=sampling,
        rules=rules,
        residual=residual,
        objective=problem.objective.name,
        objective_sampled=objective[0],
        objective_dense=objective[1],
        residual_checked=residual_checked,
        residual_passed=residual_passed,
        passed=bool(all(rule.passed for rule in rules) and residual_passed),
        mode=mode,
        seconds=time.perf_counter() - clock,
    )
    added = dense.values[list(dict.fromkeys(poses))] if poses else np.empty((0, values.shape[1]))
    added = np.vstack([added, _searched(problem, dense, x, unsearched)])
    return Check(record, _distinct(added) if added.size else added, contacts)


def _distinct(poses: np.ndarray) -> np.ndarray:
    """``poses`` (k×nv) without repeats (to 1e-9), in their order: searches from two starts may end at one pose."""
    _, first = np.unique(np.round(poses, 9), axis=0, return_index=True)  # [rad or m]: equal to 1e-9
    return poses[np.sort(first)]


def _residual(
    problem: DesignProblem, dense: _Dense, tau: np.ndarray, potential: np.ndarray
) -> tuple[list[JointResidual], tuple[float, float | None], list[int]]:
    """Per joint the residual over the samples and the poses; the objective over both (None over the
    poses for a path objective); the poses to add when a peak objective's value there exceeds the
    sampled one by more than :data:`PEAK_EXCESS` (the worst per joint above its sampled peak)."""
    rows = []
    for joint in problem.mechanism.joints:
        j = joint.index_v
        rows.append(
            JointResidual(
                joint.name,
                joint.torque_unit,
                float(np.max(np.abs(tau[:, j]))),
                float(np.max(np.abs(dense.tau[:, j]))),
                float(np.sqrt(np.mean(tau[:, j] ** 2))),
                float(np.sqrt(np.mean(dense.tau[:, j] ** 2))),
            )
        )
    objective, weights = problem.objective, problem.weights
    value = float(objective.value(tau * weights, potential, problem.path_steps))
    if objective.needs_path:
        return rows, (value, None), []
    dense_value = float(objective.value(dense.tau * weights, dense.potential, None))
    if objective.name not in PEAK_OBJECTIVES or dense_value <= (1 + PEAK_EXCESS) * value:
        return rows, (value, dense_value), []
    poses: list[int] = []
    weighted, sampled = np.abs(dense.tau * weights), np.max(np.abs(tau * weights), axis=0)
    m = dense.values.shape[0]
    for j in np.flatnonzero(weights > 0).tolist():
        order = np.argsort(-weighted[:, j], kind="stable")[:WORST_PER_RULE]
        poses += [int(i) % m for i in order if weighted[i, j] > sampled[j]]
    return rows, (value, dense_value), poses


def _clearance(checker: _Checker, dense: _Dense, x: np.ndarray) -> tuple[list[RuleMargin], list[Key]]:
    """Every spring's clearance at the poses (a pose set of ``checker``): its margin beyond
    ``Clearance.margin`` [m] where it comes closest, and the contacts below the margin."""
    index = checker.add_pose_set(dense.values)
    below, _, nearest = checker.measure(x, index)
    margin = checker.clearance.margin
    closest: dict[str, tuple[float, int, int]] = {}
    for pair, found in nearest.items():
        if not found:
            continue
        distance, _, sample = found[0]
        for name in (pair[1], pair[2]) if pair[0] == "spring" else (pair[1],):
            assert isinstance(name, str)  # a spring pair names both springs
            if name not in closest or distance < closest[name][0]:
                closest[name] = (distance, sample, pair[3])
    rules = [
        RuleMargin(
            name,
            "clearance",
            "m",
            distance - margin,
            None,
            dense.pose(sample),
            dense.scenario(scenario),
            bool(distance - margin >= -FEASIBILITY_TOLERANCE),
        )
        for name, (distance, sample, scenario) in closest.items()
    ]
    return rules, _worst(below)
