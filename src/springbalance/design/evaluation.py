"""What evaluating a design gives (:class:`Evaluation`) and the NLP the solvers see (:class:`Nlp`)."""

from __future__ import annotations

import dataclasses
from typing import Callable

import casadi as ca
import numpy as np


@dataclasses.dataclass
class Evaluation:
    """Numeric state of a design over the workspace (physical units).

    Attributes:
        x: design vector.
        tau: residual actuator torque N×nv [N·m or N].
        potential: total potential ``V_g + Σ V_s`` per sample (N) [J].
        lengths: spring states N×n_s: lengths [m] of two-point springs, joint angles [rad] of
            torsional springs.
        tensions: generalised spring forces N×n_s: tensions [N] (negative when pushing),
            torques [N·m] of torsional springs.
        constraint_rows: N×n_c, ``≥ 0`` when feasible.
    """

    x: np.ndarray
    tau: np.ndarray
    potential: np.ndarray
    lengths: np.ndarray
    tensions: np.ndarray
    constraint_rows: np.ndarray

    @property
    def max_violation(self) -> float:
        """Largest constraint violation (0 when feasible)."""
        if self.constraint_rows.size == 0:
            return 0.0
        return float(max(0.0, -np.min(self.constraint_rows)))


@dataclasses.dataclass
class Nlp:
    """The optimisation problem as the solvers see it (scaled).

    ``z`` are the scaled design variables in [0, 1] followed by any epigraph variables of the
    objective; ``cost`` and ``rows`` (≥ 0) are CasADi MX expressions of ``z``.
    """

    z: ca.MX
    lower: np.ndarray
    upper: np.ndarray
    cost: ca.MX
    rows: ca.MX
    n_design: int
    extra_start: Callable[[np.ndarray], np.ndarray] | None  # weighted tau N×nv -> starts of the extra variables

    @property
    def size(self) -> int:
        return int(self.z.numel())

    @property
    def n_rows(self) -> int:
        return int(self.rows.numel())
