r"""The design problem as the solvers see it: scaled variables, linear rows and the NLP (CasADi MX).

:class:`ProblemNlp` is the part of :class:`~springbalance.design.problem.DesignProblem` that maps the
problem's data to what a solver takes. Each design variable ``x_k ∈ [lower_k, upper_k]`` is mapped to
``z_k ∈ [0, 1]``; torques are divided by ``S``, the RMS of the unbalanced weighted gravity torque [N·m];
potentials by the standard deviation of the unbalanced potential [J]. Linear rows ``G x + h ≥ 0`` [m]
(clearance and mounting cuts) enter in units of their scale. :meth:`ProblemNlp.build` returns an
:class:`~springbalance.design.evaluation.Nlp` whose variables, bounds and expressions can be inspected or
handed to another solver.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import numpy.typing as npt

from springbalance.design import row_multipliers
from springbalance.design.clearance import LinearRows
from springbalance.design.evaluation import Nlp
from springbalance.design.objectives import Objective
from springbalance.design.torque_model import DesignVariables, TorqueModel
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace


class ProblemNlp:
    """The scaled variables, the linear rows and the NLP of a design problem (a base of ``DesignProblem``,
    which sets the attributes below)."""

    model: TorqueModel
    mechanism: Mechanism
    workspace: Workspace
    data: np.ndarray
    weights: np.ndarray
    objective: Objective
    path_steps: np.ndarray | None
    torque_scale: float
    potential_scale: float
    linear_rows: LinearRows | None

    # ---------------------------------------------------------------- variables
    @property
    def variables(self) -> DesignVariables:
        """Design variables (names, units, bounds, first guess) in physical units."""
        return self.model.variables

    def scale(self, z: np.ndarray) -> np.ndarray:
        """Physical design vector from scaled ``z ∈ [0, 1]``."""
        lower, upper = self.variables.bounds()
        return lower + (upper - lower) * np.asarray(z, dtype=float)

    def scaled_sample(self) -> tuple[ca.SX, ca.SX, tuple]:
        """``(z, data, (tau, V, L, F, C))``: the per-sample model (:attr:`TorqueModel.sample`) as SX
        expressions of the scaled variables ``z ∈ [0, 1]`` and one sample's ``data``, the data entries
        that are zero at every sample of this problem as structural zeros
        (:meth:`TorqueModel.known_zeros`): valid for this problem's samples only."""
        z = ca.SX.sym("z", self.variables.size)
        data = ca.SX.sym("data", self.model.data_size)
        lower, upper = self.variables.bounds()
        outputs = self.model.sample(ca.DM(lower) + ca.DM(upper - lower) * z, self.model.known_zeros(data, self.data))
        return z, data, tuple(outputs)

    def unscale(self, x: np.ndarray) -> np.ndarray:
        """Scaled ``z ∈ [0, 1]`` from the physical design vector (a fixed variable maps to 0)."""
        lower, upper = self.variables.bounds()
        width = np.where(upper > lower, upper - lower, 1.0)
        return (np.asarray(x, dtype=float) - lower) / width

    def linear_matrix(self) -> tuple[np.ndarray, np.ndarray]:
        """The :attr:`linear_rows` over this problem's design vector: ``(G, h)`` with rows ``G x + h ≥ 0`` [m]
        (an empty ``G`` when there are none)."""
        rows = self.linear_rows
        n = self.variables.size
        if rows is None or not len(rows):
            return np.zeros((0, n)), np.zeros(0)
        index = {name: i for i, name in enumerate(self.variables.names)}
        matrix = np.zeros((len(rows), n))
        for column, name in enumerate(rows.names):
            if name in index:
                matrix[:, index[name]] += rows.matrix[:, column]
            elif np.any(rows.matrix[:, column] != 0):
                raise InputError(f"linear rows depend on {name!r}, which is not a design variable of this problem")
        return matrix, np.asarray(rows.offset, dtype=float)

    def linear_violation(self, x: npt.ArrayLike) -> float:
        """Largest violation [m] of the :attr:`linear_rows` at design ``x`` (0 when there are none or all hold)."""
        matrix, offset = self.linear_matrix()
        if not offset.size:
            return 0.0
        return float(max(0.0, -np.min(matrix @ np.asarray(x, dtype=float) + offset)))

    # ---------------------------------------------------------------- NLP
    def build(self, objective: Objective | None = None) -> Nlp:
        """The scaled NLP (CasADi MX) for this problem: variables, bounds, cost, rows ≥ 0.

        ``objective`` replaces the problem's own (the solver builds a lexicographic objective's
        first phase this way). For ``peak_then_joints`` the NLP is its second phase, the
        ``joint_peaks`` epigraph, whose variables the solver bounds by the first phase's optimum.
        """
        design = ca.MX.sym("z", self.variables.size)
        lower, upper = self.variables.bounds()
        x = ca.DM(lower) + ca.DM(upper - lower) * design
        tau, potential, _, _, rows = self.model.mapped(self.workspace.size)(x, ca.DM(self.data))
        return self.assemble(design, tau, potential, rows, objective)

    def assemble(
        self, design: ca.MX, tau: ca.MX, potential: ca.MX, rows: ca.MX, objective: Objective | None = None
    ) -> Nlp:
        """The NLP of :meth:`build` from the per-sample outputs as given: residual torques ``tau``
        (nv×N), potentials (1×N) and constraint rows (n_c×N) as CasADi expressions of the scaled
        design variables ``design`` (or as symbols of their own: :mod:`~springbalance.design.structured_nlp`
        differentiates the NLP through them)."""
        objective = self.objective if objective is None else objective
        lower, upper = self.variables.bounds()
        weighted = ca.DM(self.weights) * tau if self.mechanism.nv > 1 else float(self.weights[0]) * tau
        pieces = objective.nlp(weighted, potential, self.path_steps, self.torque_scale, self.potential_scale)
        variables = [design]
        z_lower, z_upper = [np.zeros(self.variables.size)], [np.ones(self.variables.size)]
        if pieces.variables is not None:
            if pieces.lower is None or pieces.upper is None:
                raise AssertionError(f"objective {objective.name!r} gives epigraph variables without their bounds")
            variables.append(pieces.variables)
            z_lower.append(pieces.lower)
            z_upper.append(pieces.upper)
        all_rows = []
        if self.model.n_constraints:
            # a row that does not depend on the sample enters once, the others once per sample
            blocks = self.model.constraint_blocks
            varying = [block.offset for block in blocks if block.per_sample]
            constant = [block.offset for block in blocks if not block.per_sample]
            if varying:
                all_rows.append(ca.vec(rows[varying, :]))
            if constant:
                all_rows.append(rows[constant, 0])
        if pieces.rows is not None:
            all_rows.append(pieces.rows)
        matrix, offset = self.linear_matrix()
        if offset.size:  # G x + h = G (lower + w z) + h, in units of the rows' scale
            assert self.linear_rows is not None  # linear_matrix has rows only with linear_rows
            scale = self.linear_rows.scale
            all_rows.append(
                ca.DM(matrix * (upper - lower)[None, :] / scale) @ design + ca.DM((matrix @ lower + offset) / scale)
            )
        return Nlp(
            ca.vertcat(*variables),
            np.concatenate(z_lower),
            np.concatenate(z_upper),
            pieces.cost,
            ca.vertcat(*all_rows) if all_rows else ca.MX(0, 1),
            self.variables.size,
            pieces.start,
        )

    def nlp_row_multipliers(self, scaled: np.ndarray, n_rows: int) -> np.ndarray:
        """Multipliers of the rows of :meth:`assemble` from those of the solver's scaled rows
        (:func:`~springbalance.design.row_multipliers.nlp_row_multipliers`)."""
        return row_multipliers.nlp_row_multipliers(self.model.constraint_blocks, self.workspace.size, scaled, n_rows)

    def scaled_row_multipliers(self, nlp: np.ndarray, n_linear: int) -> np.ndarray:
        """The inverse of :meth:`nlp_row_multipliers`
        (:func:`~springbalance.design.row_multipliers.scaled_row_multipliers`)."""
        return row_multipliers.scaled_row_multipliers(self.model.constraint_blocks, self.workspace.size, nlp, n_linear)
