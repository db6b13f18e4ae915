r"""The fatigue rules of a verification (docs/model.md §3.8.2 and "Verification"): a coil's duty judged over
its real force range at the poses verified.

A coil with a duty has two auxiliary variables, bounds ``F_lo ≤ P_i ≤ F_hi`` [N] of its force at every sample,
and per location a damage row of ``(F_lo, F_hi)`` that depends on no sample
(:mod:`springbalance.springs.fatigue_rows`). The bounds are not rules: what must hold is fatigue over the range
the coil really sees. So the verification

- lowers ``F_lo`` to the coil's smallest force at the poses where that is below it, and raises ``F_hi`` to its
  largest there where that is above it (:func:`widened_bounds`): the bound rows then hold, and
- judges each damage row with that floor and the largest force at the poses, ``r(F_lo, max_j P_j)``; as the
  row falls with the force, this is the smallest of ``r(F_lo, P_j)`` over the poses, the rule the rows
  enforce at every sample (:func:`damage_rule`). The poses to add when it fails are those of the largest
  forces where ``r(F_lo, P_j)`` is broken, the worst first.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import FEASIBILITY_TOLERANCE
from springbalance.design.torque_model.variables import ConstraintBlock
from springbalance.design.verification_record import RuleMargin
from springbalance.springs.fatigue import CEILING, FLOOR
from springbalance.springs.fatigue_rows import CEILING_ROW, FLOOR_ROW, FatigueRules

#: the auxiliary variable each bound row bounds, and the sign of the change that makes the row hold
_BOUNDS = {FLOOR_ROW: (FLOOR, 1.0), CEILING_ROW: (CEILING, -1.0)}


def widened_bounds(problem: DesignProblem, dense: Any, x: np.ndarray) -> np.ndarray | None:
    """``x`` with each coil's fatigue floor ``F_lo`` [N] lowered to its smallest force at the poses verified where
    that is below it, and its ceiling ``F_hi`` raised to its largest force there where that is above it; None
    when every bound holds. ``dense``: the design's rows at the poses (``verification._Dense``); the candidates
    of a bound it moves are moved with it (its rows ``P_j - F_lo``, ``F_hi - P_j`` shift by the change, the only
    rows of the poses that depend on the bounds: the damage rows are judged by :func:`damage_rule`)."""
    widened, names = x.copy(), problem.variables.names
    for block in dense.blocks:
        if block.name not in _BOUNDS:
            continue
        key, sign = _BOUNDS[block.name]
        margin = min(dense.candidates[block.offset])[0]  # P_min - F_lo, or F_hi - P_max [N]
        name = f"{block.spring}.{key}"
        if margin < -FEASIBILITY_TOLERANCE and name in names:
            widened[names.index(name)] += sign * margin
            dense.candidates[block.offset] = [
                (value - margin, *rest) for value, *rest in dense.candidates[block.offset]
            ]
    return None if np.array_equal(widened, x) else widened


def is_damage_block(block: ConstraintBlock) -> bool:
    """Whether ``block`` is a damage row of a coil's fatigue that depends on no sample (judged by
    :func:`damage_rule`, not pose by pose)."""
    return not block.per_sample and block.name.startswith("fatigue_") and block.name not in _BOUNDS


def damage_rule(
    problem: DesignProblem, dense: Any, block: ConstraintBlock, x: np.ndarray, sampled_rows: np.ndarray, worst: int
) -> tuple[RuleMargin, list[int]]:
    """The damage rule of ``block`` at the poses verified: its margin ``r(F_lo, P_j) + reserve`` [1] at the largest
    force ``P_j`` there (``F_lo`` of ``x``, widened by :func:`widened_bounds`), the same at the largest force over
    the samples (``sampled_rows``: the rows of ``x`` there), and up to ``worst`` poses where it is broken, the
    largest forces first."""
    ceiling = next(b for b in problem.model.constraint_blocks if b.spring == block.spring and b.name == CEILING_ROW)
    spring = next(s for s in problem.springs if s.name == block.spring)
    rules = next(c for c in spring.constraints() if isinstance(c, FatigueRules))
    location = [name for name, _, _ in rules.parts if name not in _BOUNDS].index(block.name)

    def margin(ceiling_row: float, scenario: int) -> float:
        """The damage row + reserve [1] at the force ``P_j = F_hi - ceiling_row`` [N] of a pose of ``scenario``."""
        base = problem.model.scenario_vector(x, scenario)
        parameters = {**problem.model.parameter_values(spring, base), **problem.model.auxiliary_values(spring, base)}
        force = float(parameters[CEILING]) - ceiling_row
        return float(rules.damage_rows(parameters, float(parameters[FLOOR]), force)[location]) + block.reserve

    # the ceiling row's worst candidates are those of the largest forces, the largest first
    judged = [
        (margin(value, scenario), pose, scenario) for value, pose, scenario in sorted(dense.candidates[ceiling.offset])
    ]
    sampled = margin(float(np.min(sampled_rows[:, ceiling.offset])), 0)
    value, pose, scenario = judged[0]
    rule = RuleMargin(
        block.spring or "",
        block.name,
        block.unit,
        value,
        sampled,
        dense.pose(pose),
        dense.scenario(scenario),
        value >= -FEASIBILITY_TOLERANCE,
    )
    failing = list(dict.fromkeys(p for v, p, _ in judged if v < -FEASIBILITY_TOLERANCE))
    return rule, failing[:worst]
