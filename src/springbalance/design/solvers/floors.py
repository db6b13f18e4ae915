r"""A coil's fatigue floor brought down to its least force at the samples after a start.

A coil with a ``duty`` carries an auxiliary variable, its floor :math:`F_{lo}` [N]
(:mod:`springbalance.springs.fatigue_rows`): the rows :math:`P_j - F_{lo} \ge 0` hold it at or below every
sample's force ``P_j``, and the fatigue rows judge the range :math:`[F_{lo}, P_j]`. At an optimum it
touches the least force. IPOPT meets the rows to its own tolerance on the scaled NLP, where the floor's row
has a scale of 1 % of the coil's largest force (tens of N): a floor left micronewtons above the least
force is feasible to IPOPT but not to :data:`~springbalance.design.solvers.records.FEASIBILITY_TOLERANCE`
(1e-6 N), and the start was thrown away for it. :func:`lowered_floors` sets each such floor to the least
force, :math:`F_{lo} \leftarrow \min_j P_j`; the fatigue rows then judge a range wider by that much, a change
of order :math:`\Delta F / F` in their fractions of the allowable (1e-8 for µN on a coil of 100 N), and the
torque, so the objective, does not depend on the floor at all. The verification does the same at unseen
poses (:mod:`springbalance.design.verification`).
"""

from __future__ import annotations

import numpy as np

from springbalance.design.evaluation import Evaluation
from springbalance.design.solvers.records import FEASIBILITY_TOLERANCE, Problem
from springbalance.springs.fatigue import FLOOR


def lowered_floors(problem: Problem, evaluation: Evaluation) -> np.ndarray | None:
    """The design ``evaluation.x`` [physical units] with every fatigue floor that stands above its coil's least
    force at the samples by more than :data:`FEASIBILITY_TOLERANCE` lowered to that force (never below the
    floor's lower bound), or None when no floor does."""
    names = list(problem.variables.names)
    lower = problem.variables.bounds()[0]
    x = np.array(evaluation.x, dtype=float)
    changed = False
    for block in problem.model.constraint_blocks:
        name = f"{block.spring}.{FLOOR}"
        if block.name != "fatigue_floor" or not block.per_sample or name not in names:
            continue
        margin = float(np.min(evaluation.constraint_rows[:, block.offset]))  # min_j P_j − F_lo [N]
        if margin < -FEASIBILITY_TOLERANCE:
            column = names.index(name)
            x[column] = max(x[column] + margin, float(lower[column]))
            changed = True
    return x if changed else None
