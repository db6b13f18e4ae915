r"""A coil's fatigue floor brought down to its least force at the samples after a start (and its ceiling up to its
largest force).

A coil with a ``duty`` carries an auxiliary variable, its floor :math:`F_{lo}` [N]
(:mod:`springbalance.springs.fatigue_rows`): the rows :math:`P_j - F_{lo} \ge 0` hold it at or below every
sample's force ``P_j``, and the fatigue rows judge the range :math:`[F_{lo}, P_j]`. At an optimum it
touches the least force. IPOPT meets the rows to its own tolerance on the scaled NLP, where the floor's row
has a scale of 1 % of the coil's largest force (tens of N): a floor left micronewtons above the least
force is feasible to IPOPT but not to :data:`~springbalance.design.solvers.records.FEASIBILITY_TOLERANCE`
(1e-6 N), and the start was thrown away for it. :func:`lowered_floors` sets each such floor to the least
force, :math:`F_{lo} \leftarrow \min_j P_j`; the fatigue rows then judge a range wider by that much, a change
of order :math:`\Delta F / F` in their fractions of the allowable (1e-8 for µN on a coil of 100 N), and the
torque, so the objective, does not depend on the floor at all. The same holds for the ceiling :math:`F_{hi}`
(rows :math:`F_{hi} - P_j \ge 0`), raised to the largest force. The verification does the same at unseen
poses (:mod:`springbalance.design.verification_fatigue`).
"""

from __future__ import annotations

import numpy as np

from springbalance.design.evaluation import Evaluation
from springbalance.design.solvers.records import FEASIBILITY_TOLERANCE, Problem
from springbalance.springs.fatigue import CEILING, FLOOR

#: each bound row: the variable it bounds and the sign of the change that makes the row hold
_BOUNDS = {"fatigue_floor": (FLOOR, 1.0), "fatigue_ceiling": (CEILING, -1.0)}


def lowered_floors(problem: Problem, evaluation: Evaluation) -> np.ndarray | None:
    """The design ``evaluation.x`` [physical units] with every fatigue floor that stands above its coil's least
    force at the samples by more than :data:`FEASIBILITY_TOLERANCE` lowered to that force, and every ceiling
    that stands below its largest force raised to it (never beyond the variable's bounds), or None when no
    bound does."""
    names = list(problem.variables.names)
    lower, upper = problem.variables.bounds()
    x = np.array(evaluation.x, dtype=float)
    changed = False
    for block in problem.model.constraint_blocks:
        if block.name not in _BOUNDS or not block.per_sample:
            continue
        key, sign = _BOUNDS[block.name]
        name = f"{block.spring}.{key}"
        if name not in names:
            continue
        margin = float(np.min(evaluation.constraint_rows[:, block.offset]))  # min_j P_j − F_lo or F_hi − max_j P_j [N]
        if margin < -FEASIBILITY_TOLERANCE:
            column = names.index(name)
            x[column] = min(max(x[column] + sign * margin, float(lower[column])), float(upper[column]))
            changed = True
    return x if changed else None
