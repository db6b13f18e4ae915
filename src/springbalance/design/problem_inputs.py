"""The checks and defaults of a design problem's inputs: spring names, joint weights, no-joint-worse limits,
the bound on the springs' mass."""

from __future__ import annotations

import copy
from typing import Mapping, Sequence

import numpy as np

from springbalance.design.objectives import Objective, ScenarioAggregate, objective_named
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import Spring

AGGREGATES = ("sum", "worst")
#: ``no_joint_worse``: a joint's unbalanced peak counts as at least this fraction of the largest
#: joint's (of the joints with a weight > 0), so that a joint gravity does not load gets a tiny
#: positive limit rather than the impossible ``|tau| ≤ 0``.
JOINT_LIMIT_FLOOR = 1e-6


def named_springs(springs: Sequence[Spring]) -> list[Spring]:
    """The springs, unnamed ones copied and named ``s<position>`` (the caller's objects are not changed)."""
    springs = list(springs)
    if not springs:
        raise InputError("a design problem needs at least one spring")
    names = set()
    for index, spring in enumerate(springs, start=1):
        if not isinstance(spring, Spring):
            raise InputError(f"spring #{index} is a {type(spring).__name__}, not a Spring")
        if spring.name is None:
            spring = copy.copy(spring)
            spring.name = f"s{index}"
            springs[index - 1] = spring
        if spring.name in names:
            raise InputError(f"two springs are called {spring.name!r}; spring names must be unique")
        names.add(spring.name)
    return springs


def joint_limits(gravity_torque: np.ndarray, weights: np.ndarray, blocks: int) -> np.ndarray:
    """``no_joint_worse`` limits ``P_sj`` (blocks×nv) [N·m or N]: joint ``j``'s unbalanced peak
    ``max_i |g_ij|`` over the samples of scenario block ``s``, at least :data:`JOINT_LIMIT_FLOOR` times
    the block's largest one (of the weighted joints); NaN for the joints with weight 0 (no limit)."""
    peaks = np.max(np.abs(gravity_torque.reshape(blocks, -1, gravity_torque.shape[1])), axis=1)
    weighted = weights > 0
    largest = np.max(peaks[:, weighted], axis=1, keepdims=True)
    floor = JOINT_LIMIT_FLOOR * np.where(largest > 0, largest, 1.0)
    return np.where(weighted[None, :], np.maximum(peaks, floor), np.nan)


def joint_weights(mechanism: Mechanism, weights: Mapping[str, float] | None) -> np.ndarray:
    """Per-joint weights ``w_j`` (nv) from joint name → weight ≥ 0; 1 for the joints not named."""
    vector = np.ones(mechanism.nv)
    for name, value in (weights or {}).items():
        joint = mechanism.joint(name)
        value = float(value)
        if not np.isfinite(value) or value < 0:
            raise InputError(f"weight of joint {name!r} must be a finite number ≥ 0, got {value}")
        vector[joint.index_v] = value
    if not np.any(vector > 0):
        raise InputError("every joint weight is zero; nothing to balance")
    return vector


def problem_objective(objective: str | Objective, workspace: Workspace, n_scenarios: int, aggregate: str) -> Objective:
    """The objective of a problem over ``workspace`` with ``n_scenarios`` load cases combined by ``aggregate``:
    the named one, or its per-scenario aggregate (:class:`~springbalance.design.objectives.ScenarioAggregate`);
    :class:`InputError` when the workspace or the aggregate does not suit it."""
    chosen = objective_named(objective)
    if chosen.needs_path and not workspace.ordered:
        raise InputError(
            f"objective {chosen.name!r} needs an ordered workspace (grid, sweep or trajectory), "
            f"got a {workspace.description.get('kind')} sample"
        )
    if n_scenarios > 1 and aggregate == "worst" and chosen.first_phase is not None:
        raise InputError(
            f"objective {chosen.name!r} takes each joint's peak over the samples of all "
            "scenarios together; use aggregate 'sum'"
        )
    if n_scenarios > 1 and ((aggregate == "worst" and chosen.name != "peak") or chosen.name == "pe_variance"):
        # rms and peak over the stacked samples already are the sum of squares and the worst
        # case; a potential's constant differs per scenario, so its variance is taken per scenario
        chosen = ScenarioAggregate(chosen, n_scenarios, worst=aggregate == "worst")
    return chosen


def spring_mass_bound(value: object, key: str = "max_spring_mass") -> float | None:
    """``max_spring_mass`` [kg] as a float (None stays None); :class:`InputError` naming ``key`` unless it is a
    finite number > 0."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{key} must be a number > 0 [kg], got {value!r}")
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"{key} must be a finite number > 0 [kg], got {value!r}")
    return float(value)
