"""The joints a design makes worse: those that carry more torque with the springs than without them.

A joint ``j`` is carried worse when its peak ``max_i |τ_ij|`` or its RMS ``√(mean_i τ_ij²)`` over the samples
``i`` with the springs exceeds the bare arm's (gravity alone, ``g_ij``) by more than :data:`TORQUE_TOLERANCE` ×
the bare arm's largest peak (the springs' largest when gravity loads no joint) [N·m or N], or by more than the
solver's feasibility tolerance :data:`~springbalance.design.solvers.records.FEASIBILITY_TOLERANCE` when that is
larger: a design held within the bare arm's peaks (``no_joint_worse``) meets its rows within that tolerance, and
one that reaches a peak 2.4·10⁻⁸ N·m above the bare arm's (the two-link arm of
tests/design/test_verification_hold.py) carries it no worse. On a joint of weight
> 0 the command refuses such a design (the report's ``worse_joint``, exit 3); the fit to the arm and the wire
rounding prefer a design that makes no weighted joint worse (:mod:`springbalance.design.clearance_starts`,
:mod:`springbalance.design.standard_wire`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterable

import numpy as np

from springbalance.design.solvers.records import FEASIBILITY_TOLERANCE

if TYPE_CHECKING:
    from springbalance.design.problem import DesignProblem

#: torque differences below this fraction of the largest unbalanced peak are round-off
TORQUE_TOLERANCE = 1e-9


def worse_rows(rows: Iterable[dict[str, Any]], tolerance: float = TORQUE_TOLERANCE) -> list[dict[str, Any]]:
    """Of per-joint ``rows`` (``peak_before``, ``peak_after``, ``rms_before``, ``rms_after``), those carried worse,
    each with ``"worse"``: which of ``"peak"`` and ``"RMS"`` grew."""
    rows = list(rows)
    largest = max((row["peak_before"] for row in rows), default=0.0)
    if not largest > 0:  # gravity loads no joint: compare with what the springs leave
        largest = max((row["peak_after"] for row in rows), default=0.0)
    negligible = max(tolerance * largest, FEASIBILITY_TOLERANCE)
    found = []
    for row in rows:
        worse = [
            label
            for label, key in (("peak", "peak"), ("RMS", "rms"))
            if row[f"{key}_after"] - row[f"{key}_before"] > negligible
        ]
        if worse:
            found.append({**row, "worse": worse})
    return found


def torque_rows(problem: DesignProblem, tau: np.ndarray) -> list[dict[str, Any]]:
    """Per joint of ``problem``'s mechanism: its name, torque unit, and the peak and RMS over the samples of the
    bare arm's torque (``peak_before``, ``rms_before``: gravity alone) and of the residual ``tau`` (N×nv) with the
    springs (``peak_after``, ``rms_after``) [N·m or N]."""
    before = problem.workspace.kinematics().gravity_torque
    rows = []
    for joint in problem.mechanism.joints:
        j = joint.index_v
        rows.append(
            {
                "joint": joint.name,
                "unit": joint.torque_unit,
                "peak_before": float(np.max(np.abs(before[:, j]))),
                "peak_after": float(np.max(np.abs(tau[:, j]))),
                "rms_before": float(np.sqrt(np.mean(before[:, j] ** 2))),
                "rms_after": float(np.sqrt(np.mean(tau[:, j] ** 2))),
            }
        )
    return rows


def weighted_joints_made_worse(problem: DesignProblem, x: np.ndarray) -> list[str]:
    """The joints of weight > 0 that design ``x`` (physical units) carries worse than the bare arm, at the
    problem's samples."""
    rows = torque_rows(problem, problem.evaluate(np.asarray(x, dtype=float)).tau)
    weights = dict(zip((joint.name for joint in problem.mechanism.joints), problem.weights.tolist()))
    return [row["joint"] for row in worse_rows(rows) if weights.get(row["joint"], 1.0) > 0]
