"""The design problem and its solvers: variables, objectives, torque model, scenarios, exact balance.

:class:`DesignProblem` gathers a mechanism, a workspace and springs into an inspectable
problem (:meth:`DesignProblem.build`); :mod:`~springbalance.design.solvers` runs the
multi-start on it and returns a plain :class:`~springbalance.design.solvers.Solution`.
"""

from springbalance.design.objectives import OBJECTIVES, JointPeaks, Objective, PeakThenJoints
from springbalance.design.problem import DesignProblem, Evaluation
from springbalance.design.scenarios import Payload, Scenario, payload_scenarios

__all__ = [
    "OBJECTIVES",
    "DesignProblem",
    "Evaluation",
    "JointPeaks",
    "Objective",
    "Payload",
    "PeakThenJoints",
    "Scenario",
    "payload_scenarios",
]
