"""The ideal twin of a design: what the same springs would do without the rules that make them real parts.

A coil must obey its material's stress limits, a spring must keep clear of the arm; each such rule can
cost balance. The *twin* is the same problem without them: every helical coil replaced by the ideal law
of its kind with the same anchors (:mod:`springbalance.design.coil_start` solves it for the coils' first
guess), or, for a problem fitted to the arm, the multi-start's optimum before the clearance and
mounting rows were added (:mod:`springbalance.design.clearance_fit`). Its :class:`TwinRecord` keeps
what the twin achieved, so that a report can compare the finished design with it
(:mod:`springbalance.results.weak_design`): the twin's objective (in the objective's unit), the
objective without springs, and per joint of weight > 0 the reduction of its RMS torque [%],

.. math:: 100\\,\\frac{\\mathrm{rms}(g_j) - \\mathrm{rms}(\\tau_j)}{\\mathrm{rms}(g_j)},

with ``g`` the gravity torque and ``tau`` the twin's residual torque over the workspace samples.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from springbalance.design.objectives import OBJECTIVES
from springbalance.design.problem import DesignProblem


@dataclasses.dataclass(frozen=True)
class TwinRecord:
    """What the ideal twin of a design achieved (see the module documentation).

    Attributes:
        source: what the twin is, in words (``"ideal springs in place of the coils"``, ...).
        objective: the twin's objective value, in the objective's unit (over all samples, as
            :meth:`~springbalance.design.evaluated.EvaluatedDesign.metrics` gives it).
        objective_before: the objective without springs (gravity only) on the same samples.
        joints: joint name → the twin's RMS torque reduction [%], for every joint of weight > 0 that
            gravity loads.
    """

    source: str
    objective: float
    objective_before: float
    joints: dict[str, float] = dataclasses.field(default_factory=dict)

    @property
    def removed(self) -> float:
        """How much of the objective the twin removes: ``objective_before − objective`` (≥ 0 when it helps)."""
        return self.objective_before - self.objective

    def to_dict(self) -> dict[str, Any]:
        """The record in ``design.json`` (``solver.twin``)."""
        return {
            "source": self.source,
            "objective": self.objective,
            "objective_before": self.objective_before,
            "joints": dict(self.joints),
        }

    @classmethod
    def from_dict(cls, record: Any) -> TwinRecord | None:
        """The record a saved design carries (None when it has none or it is damaged)."""
        if not isinstance(record, dict):
            return None
        try:
            joints = {str(name): float(value) for name, value in dict(record.get("joints", {})).items()}
            twin = cls(str(record["source"]), float(record["objective"]), float(record["objective_before"]), joints)
        except (KeyError, TypeError, ValueError):
            return None
        return twin if math.isfinite(twin.objective) and math.isfinite(twin.objective_before) else None


def twin_record(problem: DesignProblem, x: np.ndarray, source: str) -> TwinRecord:
    """The :class:`TwinRecord` of design ``x`` of ``problem`` (the twin problem and its optimum)."""
    evaluation = problem.evaluate(np.asarray(x, dtype=float))
    kinematics = problem.workspace.kinematics()
    gravity = kinematics.gravity_torque  # N×nv [N·m or N]
    # the optimised objective over all samples, as EvaluatedDesign.metrics computes it before and after
    objective = OBJECTIVES[problem.objective.name]()
    before = objective.value(gravity * problem.weights, kinematics.potential, problem.path_steps)
    after = objective.value(evaluation.tau * problem.weights, evaluation.potential, problem.path_steps)
    negligible = 1e-9 * max(float(np.max(np.abs(gravity))), 1e-300)
    joints = {}
    for joint, weight in zip(problem.mechanism.joints, problem.weights.tolist()):
        rms_before = float(np.sqrt(np.mean(gravity[:, joint.index_v] ** 2)))
        if weight > 0 and rms_before > negligible:
            rms_after = float(np.sqrt(np.mean(evaluation.tau[:, joint.index_v] ** 2)))
            joints[joint.name] = 100.0 * (rms_before - rms_after) / rms_before
    return TwinRecord(source, float(after), float(before), joints)
