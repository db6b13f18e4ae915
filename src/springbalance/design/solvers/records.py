"""What the multi-start reports: one :class:`StartRecord` per start, and the :class:`Solution` (the best
feasible start), with the tolerances that decide feasibility and ties."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

#: what the solvers take: a :class:`~springbalance.design.problem.DesignProblem` (not imported here: the
#: problem imports the solvers, and the solvers use only its public attributes)
Problem = Any

METHODS = ("auto", "least_squares", "ipopt")
FEASIBILITY_TOLERANCE = 1e-6  # [m or N]
#: a lexicographic second phase may exceed its bound by this much of the torque scale S (IPOPT relaxes
#: bounds and rows to its tolerance); starts within it (and ``slack``) of the best value count as tied.
EPIGRAPH_TOLERANCE = 1e-6


@dataclasses.dataclass
class StartRecord:
    """What one start of the multi-start did."""

    index: int
    z0: np.ndarray
    x: np.ndarray
    objective: float
    max_violation: float
    status: str
    iterations: int
    seconds: float
    tiebreak: float = float("nan")  # second criterion of a lexicographic objective (NaN otherwise)
    #: IPOPT's multipliers of the NLP rows at ``x`` (CasADi's sign, ≤ 0) when IPOPT ended the start, else None
    multipliers: np.ndarray | None = None

    @property
    def feasible(self) -> bool:
        """Every constraint row within :data:`FEASIBILITY_TOLERANCE` [m or N] and a finite objective."""
        return self.max_violation <= FEASIBILITY_TOLERANCE and np.isfinite(self.objective)

    def to_dict(self) -> dict[str, Any]:
        """The record as JSON-ready values (``x`` as a list; ``tiebreak`` only when it is set)."""
        return {
            "index": self.index,
            "objective": self.objective,
            "max_violation": self.max_violation,
            "status": self.status,
            "iterations": self.iterations,
            "seconds": self.seconds,
            "feasible": bool(self.feasible),
            "x": self.x.tolist(),
            **({"tiebreak": self.tiebreak} if np.isfinite(self.tiebreak) else {}),
        }


@dataclasses.dataclass
class Solution:
    """What the multi-start found: the best feasible design vector and the record of every start.

    Attributes:
        x: the chosen design vector in physical units (``problem.variables.names`` order).
        starts: one :class:`StartRecord` per start (polished starts replace their screening record).
        method: the solver method asked for (``auto``, ``least_squares`` or ``ipopt``).
        seed: the seed of the start points.
        status: the solver status of the chosen start.
        multipliers: IPOPT's multipliers of the NLP rows at ``x`` when IPOPT ended the chosen start (else
            None): a solve of a nearby problem with the same rows may start from them (``solve_problem``).
    """

    x: np.ndarray
    starts: list[StartRecord]
    method: str
    seed: int
    status: str
    multipliers: np.ndarray | None = None
