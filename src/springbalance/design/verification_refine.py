"""A coil's length and force rules searched to their worst poses inside the workspace's box, for the verification.

A coil must never go slack: ``L(q) ≥ l0``. ``L`` is smooth in the joint values, and its least value over a box
of joint ranges lies, for most layouts, on the box's boundary (a joint at its limit), which Sobol points
approach but never reach: a design that touches ``l0`` at its samples can be a fraction of a millimetre slack
at the limit (the UR5 example: 0.48 mm at the elbow's limit, found at one of 16,384 poses and at none of the
verification's 2,560). Its largest force (and with it every stress of the coil) lies there too, at the longest
length of an extension coil and the shortest of a compression coil. :func:`refined_poses` starts from the worst
poses the verification found for each rule of :data:`RULES`, a few far apart (:func:`search_starts`), and runs a compass search (Kolda, Lewis & Torczon, SIAM Review 45(3), 2003,
§3): try ``±h_j`` along each joint ``j``, clipped to its range, move to the best pose that lowers the margin,
else halve every ``h``; ``h`` starts at :data:`FIRST_STEP` of each range and stops after :data:`HALVINGS`
halvings. Only a box workspace without couplings is searched (the couplings tie joints that the search would
move alone). The verification judges the rule at these poses besides its Sobol poses.
"""

from __future__ import annotations

import numpy as np

from springbalance.design.problem import DesignProblem
from springbalance.design.scenarios import ScenarioWorkspace
from springbalance.design.torque_model import BlockEvaluator
from springbalance.design.torque_model.variables import ConstraintBlock
from springbalance.model.workspace import Workspace

#: the rules searched (:func:`searched`): a helical extension coil's length ``L − l0`` [m], a helical compression
#: coil's ``l0 − L`` at its longest length, and a helical coil's body stress, at its largest force (the hooks'
#: stresses and the fatigue ceiling grow with the same force; a compression coil's solid length and buckling
#: bind at the same, shortest, length)
RULES = ("tension", "stays_compressed", "body_stress")


def searched(block: ConstraintBlock) -> bool:
    """Whether the verification searches ``block``: a per-sample row of :data:`RULES` that the optimisation keeps a
    reserve for (a helical coil's: the search finds the rule's extreme between the samples, and the reserve lets
    a re-solve hold it there when it moves; an ideal spring's ``L ≥ l0`` keeps none and is not searched)."""
    return block.per_sample and block.name in RULES and block.reserve > 0


#: the first step along each joint, as a fraction of its range [1]
FIRST_STEP = 0.125
#: halvings of the step before the search stops (the last step is FIRST_STEP / 2^HALVINGS of a range)
HALVINGS = 8
#: most rounds of trials (each moves or halves every search still running)
MAX_ROUNDS = 60
#: searches per rule, from its worst poses at least APART of the box from each other along some joint
STARTS_PER_RULE = 4
APART = 0.25


def search_box(workspace: Workspace) -> tuple[np.ndarray, np.ndarray] | None:
    """``(lower, upper)`` [rad or m] of a workspace drawn over a box of joint ranges without couplings, else
    None (a path, an array of poses, coupled joints)."""
    description = workspace.description
    if "lower" not in description or "upper" not in description or description.get("couplings"):
        return None
    return np.array(description["lower"], dtype=float), np.array(description["upper"], dtype=float)


def evaluated_at(problem: DesignProblem, x: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The residual torque (n×nv), potential (n) and constraint rows (n×rows) of design ``x`` at ``poses`` (k×nv),
    in every scenario of the problem in turn (``n = k·S``: the poses of scenario 0, then of scenario 1 …)."""
    workspace = Workspace(problem.mechanism, poses, description={"kind": "verification"})
    stacked = ScenarioWorkspace(workspace, problem.scenarios) if problem.scenarios else workspace
    evaluator = BlockEvaluator(problem.sample_function(), problem.model.data_matrix(stacked.kinematics()))
    tau, potential, _, _, rows = evaluator.evaluate(x)
    n = stacked.size
    return np.asarray(tau).reshape(n, -1), np.asarray(potential).reshape(n), np.asarray(rows).reshape(n, -1)


def margins(problem: DesignProblem, x: np.ndarray, poses: np.ndarray, blocks: list[ConstraintBlock]) -> np.ndarray:
    """The rows of ``blocks`` (plus their reserves) of design ``x`` at ``poses`` (k×nv), the least over the
    problem's scenarios: a k×len(blocks) array [each block's unit]."""
    rows = evaluated_at(problem, x, poses)[2]
    columns = rows[:, [block.offset for block in blocks]] + np.array([block.reserve for block in blocks])
    return columns.reshape(-1, poses.shape[0], len(blocks)).min(axis=0)


def search_starts(
    problem: DesignProblem,
    x: np.ndarray,
    values: np.ndarray,
    box: tuple[np.ndarray, np.ndarray],
    blocks: list[ConstraintBlock] | None = None,
    at: np.ndarray | None = None,
) -> list[tuple[int, np.ndarray]]:
    """Where the searches start: per rule, up to :data:`STARTS_PER_RULE` of the poses ``values`` (M×nv)
    with its least margins, each at least :data:`APART` of the box from the others along some joint (so that
    they start near different minima); ``(block offset, pose)`` pairs. ``blocks`` and ``at`` (M × len(blocks)):
    the rules' blocks and their :func:`margins` at ``values``, when the caller has them already."""
    if blocks is None:
        blocks = [block for block in problem.model.constraint_blocks if searched(block)]
    if not blocks or not values.size:
        return []
    if at is None:
        at = margins(problem, x, values, blocks)
    scale = np.where(box[1] > box[0], box[1] - box[0], 1.0)
    starts = []
    for column, block in enumerate(blocks):
        order = np.argsort(at[:, column], kind="stable")
        relevant = spring_joints(problem, block)
        chosen: list[np.ndarray] = []  # greedily, in order: each pose APART from those chosen before it
        while order.size and len(chosen) < STARTS_PER_RULE:
            chosen.append(values[order[0]])
            gaps = np.abs(values[order[1:]] - chosen[-1])[:, relevant] / scale[relevant]
            order = order[1:][np.max(gaps, axis=1, initial=0.0) >= APART]
        starts += [(block.offset, pose) for pose in chosen]
    return starts


def refined_poses(
    problem: DesignProblem, x: np.ndarray, starts: list[tuple[int, np.ndarray]], box: tuple[np.ndarray, np.ndarray]
) -> np.ndarray:
    """Each start ``(block offset, pose)`` searched to a local minimum of its block's margin within ``box`` (see
    the module documentation); the poses (rows, in the order of ``starts``). A search moves only the joints its
    spring depends on (:func:`spring_joints`)."""
    if not starts:
        return np.empty((0, box[0].size))
    lower, upper = box
    by_offset = {block.offset: block for block in problem.model.constraint_blocks}
    offsets = list(dict.fromkeys(offset for offset, _ in starts))
    blocks = [by_offset[offset] for offset in offsets]
    column = np.array([offsets.index(offset) for offset, _ in starts])
    poses = np.array([pose for _, pose in starts], dtype=float)
    current = margins(problem, x, poses, blocks)[np.arange(len(starts)), column]
    joints = {offset: np.flatnonzero((upper > lower) & spring_joints(problem, by_offset[offset])) for offset in offsets}
    moving = [joints[offset] for offset, _ in starts]
    steps = np.tile(FIRST_STEP * (upper - lower), (len(starts), 1))
    halvings = np.array([0 if joints.size else HALVINGS + 1 for joints in moving])
    for _ in range(MAX_ROUNDS):
        active = np.flatnonzero(halvings <= HALVINGS)
        if not active.size:
            break
        trials, owner = [], []  # per active search: 2 neighbours along each joint it moves
        for s in active:
            for j in moving[s]:
                for sign in (1.0, -1.0):
                    trial = poses[s].copy()
                    trial[j] = np.clip(trial[j] + sign * steps[s, j], lower[j], upper[j])
                    trials.append(trial)
                    owner.append(s)
        values, owners = margins(problem, x, np.array(trials), blocks), np.array(owner)
        for s in active:
            rows = np.flatnonzero(owners == s)
            best = rows[int(np.argmin(values[rows, column[s]]))]
            if values[best, column[s]] < current[s]:
                poses[s], current[s] = trials[best], values[best, column[s]]
            else:
                steps[s] *= 0.5
                halvings[s] += 1
    return poses


def spring_joints(problem: DesignProblem, block: ConstraintBlock) -> np.ndarray:
    """Which joint coordinates (nv bools) move the points of ``block``'s spring relative to each other: those of
    the joints that support some of its bodies but not all (a joint that supports them all moves the spring as a
    rigid whole; a URDF mimic joint counts as its primary's coordinate). Every coordinate for a block of no spring."""
    mechanism = problem.mechanism
    spring = next((s for s in problem.springs if s.name == block.spring), None)
    if spring is None or not hasattr(spring, "anchors"):
        return np.ones(mechanism.nv, dtype=bool)
    model = mechanism.model
    chains = [
        set(model.supports[model.frames[mechanism.frame_id(anchor.body)].parentJoint])
        for anchor in spring.anchors.values()
    ]
    moved = np.zeros(mechanism.nv, dtype=bool)
    for joint in set.union(*chains) - set.intersection(*chains):
        moved[model.joints[joint].idx_v : model.joints[joint].idx_v + max(model.joints[joint].nv, 1)] = True
    return moved
