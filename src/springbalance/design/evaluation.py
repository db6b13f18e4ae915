"""What evaluating a design gives (:class:`Evaluation`) and the NLP the solvers see (:class:`Nlp`)."""

from __future__ import annotations

import dataclasses
from typing import Any, Callable, Sequence

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
        row_units: per column of ``constraint_rows``, the size of its unit in those of :attr:`max_violation`
            (:data:`ROW_UNITS`; None: 1 for every column).
    """

    x: np.ndarray
    tau: np.ndarray
    potential: np.ndarray
    lengths: np.ndarray
    tensions: np.ndarray
    constraint_rows: np.ndarray
    row_units: np.ndarray | None = None

    @property
    def max_violation(self) -> float:
        """Largest constraint violation (0 when feasible): in m, N or as a fraction (of an allowable stress), a
        row in MPa in units of 100 MPa (:data:`ROW_UNITS`), so that one feasibility tolerance fits them all."""
        if self.constraint_rows.size == 0:
            return 0.0
        rows = self.constraint_rows if self.row_units is None else self.constraint_rows / self.row_units
        return float(max(0.0, -np.min(rows)))


#: A row's unit → its size in the units of :attr:`Evaluation.max_violation`: a stress row in MPa (a coil's initial
#: stress against the band it can be wound in, about 100 MPa wide) counts in units of 100 MPa, as a stress row
#: in fractions of its allowable does; m, N and fractions count as they are. (At 1e-6 MPa, a tolerance meant
#: for metres, a Panda coil whose IPOPT solve had succeeded failed as infeasible by 2.6 Pa.)
ROW_UNITS = {"MPa": 100.0}


def row_units(blocks: Sequence[Any]) -> np.ndarray | None:
    """:attr:`Evaluation.row_units` of the constraint columns ``blocks`` (each with its ``unit``; the model's
    :attr:`constraint_blocks`, one column each), None when every unit counts as it is."""
    units = np.array([ROW_UNITS.get(block.unit, 1.0) for block in blocks])
    return units if np.any(units != 1.0) else None


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
