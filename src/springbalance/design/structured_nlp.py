r"""IPOPT's derivatives from the per-sample structure of the NLP (docs/model.md §6, "How IPOPT sees the NLP").

Every NLP of :meth:`~springbalance.design.problem.DesignProblem.build` is a function of the scaled
design variables ``z`` *through the per-sample outputs* ``y_s = (τ_s, V_s, c_s)`` (residual torques,
potential, constraint rows of sample ``s``), plus the objective's extra variables ``e`` (epigraph
bounds) and rows linear in ``z``:

.. math::
    \min_{w=(z,e)} f(Y(z), w) \quad \text{s.t.}\quad g(Y(z), w) \ge 0, \qquad Y = [y_1 \dots y_N].

``f`` and ``g`` (:meth:`~springbalance.design.problem.DesignProblem.assemble`) are cheap: sums,
differences and squares of the entries of ``Y``. The costly part is ``Y(z)``, one small function per
sample. With ``J_s = ∂y_s/∂z`` (m × n, from one compiled per-sample function) the chain rule gives

- ``∇f = Σ_s J_sᵀ ∂f/∂y_s + ∂f/∂w`` and ``∂g/∂z = Σ_s ∂g/∂y_s J_s``;
- for the Lagrangian ``L = λ_f f + λ_gᵀ g`` and ``ȳ_s = ∂L/∂y_s``:

  .. math::
      \nabla^2_{zz} L = \sum_s \nabla^2_{zz}\big(\bar y_s^\mathsf{T} y_s(z)\big)
                      + \sum_{s,t} J_s^\mathsf{T}\,\frac{\partial^2 L}{\partial y_s \partial y_t}\,J_t .

  The first term is one compiled per-sample function of ``(z, data_s, ȳ_s)`` (an n × n Hessian,
  summed over the samples in C). The second is a Gauss–Newton-like term: zero when ``f`` and ``g``
  are linear in ``Y`` (``peak``, ``joint_peaks``, ``energy``, every constraint row). When
  ``∂²L/∂Y²`` is diagonal (``rms``: ``2λ_f c`` on the torques), it is ``Σ_s J_kᵀ diag(d_s) J_k`` over
  the outputs ``k`` where the diagonal has entries, and the same compiled per-sample function adds
  it (its input ``d_s`` comes from CasADi's ``∂²L/∂Y²``). Otherwise CasADi forms it as ``n`` forward
  directions through ``∂L/∂Y``.

This is the *exact* Hessian of the Lagrangian, at the cost of one pass over the samples, instead of
CasADi differentiating the mapped MX graph twice (``n`` forward-over-reverse sweeps of every sample
on its interpreter). The extra variables enter ``f`` and ``g`` linearly (checked when the NLP is
built, else :class:`StructuredNlp` refuses and the solver differentiates the plain NLP), so the
Hessian has only its ``z``–``z`` block.

**Working set.** An interior-point method keeps every row of ``g`` in its linear systems, and most
rows never matter: of the ``2·N·nv`` epigraph rows of ``peak`` only those of the worst samples bind,
of a coil's stress rows only those of its longest stretch. :meth:`StructuredNlp.solve` gives IPOPT
the rows that are violated or among the :data:`WORKING_ROWS` closest to binding (at least
:data:`ROWS_PER_VARIABLE` per variable) at the start, solves, evaluates *every* row at the solution,
adds the rows found violated (and the next closest), and solves again from there, until no row
outside the set is violated: the answer then satisfies the full NLP's KKT conditions, as if all rows
had been there (a solve with helical coils may end on a plateau of its objective instead of at IPOPT's tolerance:
:mod:`~springbalance.design.plateau`). The maps over the samples run only over the samples that the cost and the
rows in the set depend on (all of them for ``rms``, a few hundred for ``peak``); the rows and their Jacobian
only over the samples of the rows (:meth:`StructuredNlp.callbacks`), that Jacobian a constant for affine rows.
A bound over the samples (a coil's fatigue floor ``P_i - F_lo ≥ 0`` or ceiling) starts with the rows of its
:data:`EXTREME_SAMPLES` smallest samples.

**Rows evaluated once.** A row of no sample enters the NLP once (from sample 0's outputs), but the
per-sample functions compute it at every sample. The rows a constraint marks ``once`` (a coil's fatigue
damage rows: costly, of four variables) are left out of the per-sample functions and evaluated, with their
Jacobian and Hessian, once per call (:meth:`StructuredNlp._once`).
"""

from __future__ import annotations

from typing import Any, Callable

import casadi as ca
import numpy as np

from springbalance.design.output_structure import (
    RestrictedNlp,
    diagonal_curvature,
    linear_in,
    row_structure,
    samples_of,
)
from springbalance.design.plateau import PLATEAU_STATUS, Plateau, stops_on_plateau
from springbalance.design.torque_model import compiled


class NotStructured(ValueError):
    """The NLP does not have the structure :class:`StructuredNlp` relies on (the caller falls back)."""


#: rows IPOPT starts with: the violated ones and the closest to binding, at least this many ...
WORKING_ROWS = 64
#: ... and this many per variable
ROWS_PER_VARIABLE = 6
#: ... and every row of this many samples, the first ones (Sobol and grid prefixes spread over the workspace)
SPREAD_SAMPLES = 64
#: ... but of a bound over the samples (:attr:`ConstraintBlock.extreme`), the rows of this many samples where it is
#: smallest instead
EXTREME_SAMPLES = 4
#: how far a warm-started round pushes its start point and multipliers into the interior (IPOPT's adaptive barrier
#: strategy then picks the barrier parameter itself: its ``mu_init`` counts only for the monotone one, 1.5-2× slower)
WARM_PUSH = 1e-6
#: a row outside the working set counts as violated below this (scaled units, as IPOPT's ``tol``)
ROW_TOLERANCE = 1e-8
#: IPOPT statuses after which a further round may follow (not after a failure or the iteration limit)
CONVERGED = ("Solve_Succeeded", "Solved_To_Acceptable_Level", PLATEAU_STATUS)
#: working-set rounds at most (each adds rows; the last one solves with every row still missing)
MAX_ROUNDS = 12


class StructuredNlp:
    """IPOPT on ``problem``'s NLP (of ``objective``) with its gradient, constraint Jacobian and
    Lagrangian Hessian from compiled per-sample functions, on a growing working set of rows (see
    the module docstring).

    Attributes:
        nlp: the :class:`~springbalance.design.problem.Nlp`: variables, bounds, extra starts (its ``cost``
            and ``rows`` are expressions of per-sample output symbols: solve with :meth:`solve`).
    """

    def __init__(self, problem: Any, objective: Any = None) -> None:
        model = problem.model
        self.n_samples, nv, n_c = problem.workspace.size, problem.mechanism.nv, model.n_constraints
        self.n_design = n_x = problem.variables.size
        self.n_outputs = m = nv + 1 + n_c

        # the NLP over symbols of the per-sample outputs (vec(Y), sample by sample)
        self._outputs = ca.MX.sym("Y", m * self.n_samples)
        grid = ca.reshape(self._outputs, m, self.n_samples)
        design = ca.MX.sym("z", n_x)
        self.nlp = nlp = problem.assemble(design, grid[:nv, :], grid[nv, :], grid[nv + 1 :, :], objective)
        both = ca.vertcat(nlp.cost, nlp.rows)
        if nlp.size > n_x and not linear_in(both, ca.vertcat(*nlp.z.primitives()[1:])):
            raise NotStructured("the objective's extra variables enter its NLP nonlinearly")
        if not linear_in(both, design):
            raise NotStructured("the NLP depends nonlinearly on the design variables other than through the samples")
        self.n_rows = int(nlp.rows.numel())
        self.stops_on_plateau = stops_on_plateau(problem)
        self.extra_start: Callable[[np.ndarray], np.ndarray] | None = None
        if nlp.size > n_x:
            starts = nlp.extra_start
            assert starts is not None  # an NLP with extra (epigraph) variables has their start

            def extra_start(z: np.ndarray) -> np.ndarray:
                return starts(problem.evaluate(problem.scale(z)).tau * problem.weights)

            self.extra_start = extra_start
        # the first sample each row depends on, and the Jacobians of affine rows (constants)
        self._row_sample, self._row_jacobians = row_structure(nlp.rows, self._outputs, nlp.z, m)

        # the outputs k of a sample on which ∂²L/∂Y² has its (diagonal) entries; None when it is not diagonal
        self._curved = diagonal_curvature(ca.vertcat(nlp.cost, nlp.rows), self._outputs, m)
        self._curved_list = [] if self._curved is None else self._curved.tolist()

        # per sample, compiled: y_s, then y_s with J_sᵀ, then the Hessian of ȳ_sᵀ y_s (+ J_kᵀ diag(d) J_k)
        z, data, (tau, potential, _, _, rows) = problem.scaled_sample()
        weights = ca.SX.sym("ybar", m)
        y = ca.vertcat(tau, potential, rows)
        y = self._split_once(model.constraint_blocks, nv, z, y)
        hessian, _ = ca.hessian(ca.dot(weights, y), z)
        curved = self._curved_list
        curvature = ca.SX.sym("d", len(curved))
        if curved:
            jacobian = ca.jacobian(y[curved], z)
            hessian += ca.mtimes(jacobian.T, ca.diag(curvature) @ jacobian)
        self._sample_outputs = compiled(ca.Function("sample_outputs", [z, data], [y]))
        self._sample_jacobian = compiled(ca.Function("sample_jacobian", [z, data], [y, ca.jacobian(y, z).T]))
        self._sample_hessian = compiled(
            ca.Function("sample_hessian", [z, data, weights, curvature], [ca.triu(hessian)])
        )
        self._data = np.asarray(problem.data)
        # the varying rows come sample by sample (problem.assemble): block b of sample s is row s·n_varying + b
        varying = [block for block in model.constraint_blocks if block.per_sample]
        self._extreme = [(b, len(varying)) for b, block in enumerate(varying) if block.extreme]
        x = ca.MX.sym("x", nlp.size)
        every_output = self._mapped(np.arange(self.n_samples), x[:n_x])[0]
        self._all_rows = ca.Function(
            "all_rows", [x], [ca.Function("g", [self._outputs, nlp.z], [nlp.rows])(every_output, x)]
        )

    def _split_once(self, blocks: list, nv: int, z: ca.SX, y: ca.SX) -> ca.SX:
        """``y`` with the rows evaluated once (:attr:`ConstraintBlock.once`: rows of no sample, a coil's fatigue
        damage rows) set to 0; those rows, their Jacobian and their Hessian become functions of ``z`` alone,
        which :meth:`_once` adds to sample 0's outputs (the only sample the NLP reads a row of no sample from)."""
        once = [
            nv + 1 + block.offset for block in blocks if block.once and nv + 1 + block.offset not in self._curved_list
        ]
        self._once_rows = np.array(once, dtype=int)
        if not once:
            return y
        values = y[once]
        weights = ca.SX.sym("w", len(once))
        # a few rows of a few variables, evaluated once per call: CasADi's virtual machine, not worth a compiler run
        self._once_jacobian = ca.Function("once_jacobian", [z], [values, ca.jacobian(values, z).T])
        self._once_hessian = ca.Function(
            "once_hessian", [z, weights], [ca.triu(ca.hessian(ca.dot(weights, values), z)[0])]
        )
        kept = ca.SX(y)
        for row in once:
            kept[row] = 0
        return kept

    def _once(self, samples: np.ndarray, z: ca.MX) -> tuple[ca.DM, ca.MX, ca.MX] | None:
        """``(S, c, J_cᵀ)``: the rows evaluated once at ``z``, their Jacobian transposed, and the 0/1 matrix ``S``
        that places them in sample 0's outputs within vec(Y) of ``samples``; None without such rows (or without
        sample 0)."""
        if not self._once_rows.size or samples.size == 0 or samples[0] != 0:
            return None
        count = self._once_rows.size
        place = ca.DM(
            ca.Sparsity.triplet(self.n_outputs * samples.size, count, self._once_rows.tolist(), list(range(count))), 1.0
        )
        values, transposed = self._once_jacobian(z)
        return place, values, transposed

    def _positions(self, samples: np.ndarray) -> np.ndarray:
        """The positions in vec(Y) of the outputs of ``samples``, sample by sample."""
        return (samples[:, None] * self.n_outputs + np.arange(self.n_outputs)[None, :]).reshape(-1)

    def _scatter(self, samples: np.ndarray) -> ca.DM:
        """The sparse 0/1 matrix that places the outputs of ``samples`` in vec(Y) (zeros elsewhere)."""
        positions, size = self._positions(samples), self.n_outputs * self.n_samples
        return ca.DM(ca.Sparsity.triplet(size, positions.size, positions.tolist(), list(range(positions.size))), 1.0)

    def row_values(self, x: np.ndarray) -> np.ndarray:
        """Every row of the NLP at ``x`` (design and extra variables, scaled)."""
        return np.array(self._all_rows(x)).reshape(-1)

    def _solver(self, rows: np.ndarray, options: dict) -> tuple[ca.Function, Plateau | None]:
        """IPOPT on the NLP restricted to ``rows`` (derivatives through their samples) and its plateau callback."""
        x, cost, constraints, derivatives = self.callbacks(rows)
        options = {**options, **derivatives, "calc_lam_p": False, "no_nlp_grad": True}
        plateau = None
        if self.stops_on_plateau:  # a plateau stops the solve only where the rows outside ``rows`` are met too
            outside = np.setdiff1d(np.arange(self.n_rows), rows)
            met = lambda point: bool(np.all(self.row_values(point)[outside] >= -ROW_TOLERANCE))  # noqa: E731
            options["iteration_callback"] = plateau = Plateau(int(x.numel()), int(constraints.numel()), met)
        return ca.nlpsol("springbalance", "ipopt", {"x": x, "f": cost, "g": constraints}, options), plateau

    def _restricted(self, rows: np.ndarray) -> RestrictedNlp:
        """The NLP restricted to ``rows`` as functions of the outputs of the samples it uses."""
        nlp, n_x, m = self.nlp, self.n_design, self.n_outputs
        f, g = nlp.cost, nlp.rows[rows.tolist()] if rows.size < self.n_rows else nlp.rows
        samples, row_samples = samples_of(ca.vertcat(f, g), self._outputs, m), samples_of(g, self._outputs, m)
        samples, row_samples = (found if found.size else np.zeros(1, dtype=int) for found in (samples, row_samples))
        phi = ca.Function("phi", [self._outputs, nlp.z], [f, g])
        local, local_rows = ca.MX.sym("Y", m * samples.size), ca.MX.sym("Y_rows", m * row_samples.size)
        f_local, g_all = phi(self._scatter(samples) @ local, nlp.z)
        g_local = phi(self._scatter(row_samples) @ local_rows, nlp.z)[1]
        n_g = int(g_local.numel())
        lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", n_g)
        ybar = ca.gradient(lam_f * f_local + ca.dot(lam_g, g_all), local)
        # ȳ does not depend on Y when f and g are linear in Y (epigraphs, constraint rows); when ∂²L/∂Y² is
        # diagonal (rms), its diagonal is ∂²L/∂Y² 1 and the per-sample Hessian adds J_kᵀ diag(d_k) J_k itself;
        # otherwise the Gauss–Newton-like term is Jᵀ (∂²L/∂Y²) J, n forward directions through ȳ
        linear = not ca.depends_on(ybar, local)
        diagonal = not linear and self._curved is not None
        curved = self._curved_list
        if linear or diagonal:
            curvature = (
                ca.reshape(ca.jtimes(ybar, local, ca.DM.ones(m * samples.size)), m, samples.size)[curved, :]
                if diagonal
                else ca.MX(len(curved), samples.size)
            )
            hessian = ca.Function("phi_hessian", [local, nlp.z, lam_f, lam_g], [ybar, curvature])
        else:
            directions = ca.MX.sym("J", m * samples.size, n_x)
            hessian = ca.Function(
                "phi_hessian",
                [local, nlp.z, lam_f, lam_g, directions],
                [ybar, ca.mtimes(directions.T, ca.jtimes(ybar, local, directions))],
            )
        return RestrictedNlp(
            samples,
            row_samples,
            n_g,
            linear,
            diagonal,
            ca.Function("cost", [local, nlp.z], [f_local]),
            ca.Function(
                "cost_gradient", [local, nlp.z], [f_local, ca.gradient(f_local, local), ca.gradient(f_local, nlp.z)]
            ),
            ca.Function("rows", [local_rows, nlp.z], [g_local]),
            self._rows_jacobian(rows, row_samples, local_rows, g_local),
            hessian,
        )

    def _rows_jacobian(self, rows: np.ndarray, samples: np.ndarray, local: ca.MX, g: ca.MX) -> ca.Function:
        """``(Y_rows, w) → (g, (∂g/∂Y_rows)ᵀ, ∂g/∂w)`` of ``rows`` (``g``, an expression of ``local``: the outputs of
        ``samples``): the Jacobians as constants when every row is affine, else through CasADi's scalar graph."""
        w = self.nlp.z
        if self._row_jacobians is None:
            return ca.Function("rows_jacobian", [local, w], [g, ca.jacobian(g, local).T, ca.jacobian(g, w)]).expand()
        by_outputs, by_variables = self._row_jacobians
        columns = self._positions(samples).tolist()
        return ca.Function(
            "rows_jacobian", [local, w], [g, by_outputs[rows.tolist(), columns].T, by_variables[rows.tolist(), :]]
        )

    def _mapped(self, samples: np.ndarray, z: ca.MX) -> tuple[ca.MX, ca.MX, ca.MX, ca.MX, tuple | None]:
        """Over ``samples`` at ``z``: ``(Y, Y, Jᵀ, data, once)``: their outputs (from the outputs' map, then from the
        Jacobians' map) with the rows evaluated once added to sample 0's, the Jacobians transposed (n × m·count),
        the samples' data and :meth:`_once`'s result."""
        count, columns = samples.size, ca.MX(ca.DM(self._data[:, samples]))
        values = ca.vec(self._sample_outputs.map("outputs", "serial", count, [0], [])(z, columns))
        values_j, transposed = self._sample_jacobian.map("jacobian", "serial", count, [0], [])(z, columns)
        values_j = ca.vec(values_j)
        once = self._once(samples, z)
        if once is not None:  # the rows evaluated once, in sample 0's outputs
            place, once_values, once_transposed = once
            values, values_j = values + place @ once_values, values_j + place @ once_values
            transposed = transposed + ca.mtimes(once_transposed, place.T)
        return values, values_j, transposed, columns, once

    def callbacks(self, rows: np.ndarray) -> tuple:
        """``(x, f, g, {"grad_f", "jac_g", "hess_lag"})`` of the NLP restricted to ``rows``: the variables,
        cost and rows as MX expressions, and the three derivative functions with the signatures IPOPT's
        interface expects (``nlp_grad_f``, ``nlp_jac_g``, ``nlp_hess_l``). The cost, its gradient and the
        Hessian map over the samples the cost or the rows use; the rows and their Jacobian over the rows'
        samples only (for ``rms``, a few hundred of the workspace's samples)."""
        nlp, n_x, m = self.nlp, self.n_design, self.n_outputs
        restricted = self._restricted(rows)
        samples, n_g, count, curved = restricted.samples, restricted.n_g, restricted.samples.size, self._curved_list

        # the oracle and its derivatives, as IPOPT's callbacks expect them
        x, p = ca.MX.sym("x", nlp.size), ca.MX.sym("p", 0)
        zx, n_extra = x[:n_x], nlp.size - n_x
        values, values_j, transposed, columns, once = self._mapped(samples, zx)
        row_values, row_values_j, row_transposed, _, _ = self._mapped(restricted.row_samples, zx)
        cost, constraints = restricted.cost(values, x), restricted.rows(row_values, x)
        cost_j, cost_y, cost_w = restricted.cost_gradient(values_j, x)
        grad_f = ca.Function(
            "nlp_grad_f",
            [x, p],
            [cost_j, cost_w + ca.vertcat(ca.mtimes(transposed, cost_y), ca.MX(n_extra, 1))],
            ["x", "p"],
            ["f", "grad_f_x"],
        )
        rows_j, rows_y_transposed, rows_w = restricted.rows_jacobian(row_values_j, x)
        jac_g = ca.Function(
            "nlp_jac_g",
            [x, p],
            [rows_j, rows_w + ca.horzcat(ca.mtimes(row_transposed, rows_y_transposed).T, ca.MX(n_g, n_extra))],
            ["x", "p"],
            ["g", "jac_g_x"],
        )
        weight_f, weight_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", n_g)
        if restricted.linear or restricted.diagonal:  # only the samples' Hessians (and outputs, when diagonal)
            ybar_value, diagonal_value = restricted.hessian(
                values if restricted.diagonal else ca.MX(m * count, 1), x, weight_f, weight_g
            )
            gauss_newton = ca.MX(n_x, n_x)
        else:
            ybar_value, gauss_newton = restricted.hessian(values_j, x, weight_f, weight_g, transposed.T)
            diagonal_value = ca.MX(len(curved), count)
        summed = self._sample_hessian.map("hessian", "serial", count, [0], [0])(
            zx, columns, ca.reshape(ybar_value, m, count), diagonal_value
        )
        if once is not None:
            summed = summed + self._once_hessian(zx, ca.mtimes(once[0].T, ybar_value))
        hessian = ca.diagcat(summed + ca.triu(gauss_newton), ca.MX(n_extra, n_extra))
        hess_lag = ca.Function(
            "nlp_hess_l",
            [x, p, weight_f, weight_g],
            [ca.triu(hessian)],
            ["x", "p", "lam_f", "lam_g"],
            ["triu_hess_gamma_x_x"],
        )
        return x, cost, constraints, {"grad_f": grad_f, "jac_g": jac_g, "hess_lag": hess_lag}

    def solve(
        self,
        start: np.ndarray,
        lower: np.ndarray,
        upper: np.ndarray,
        options: dict,
        max_iterations: int,
        lam_g: np.ndarray | None = None,
    ) -> tuple[np.ndarray, str, int, np.ndarray]:
        """IPOPT from ``start`` (design and extra variables) within the bounds, rows ≥ 0, on a working set
        grown until no other row is violated. Returns ``(x, IPOPT's status, iterations, lam_g)``: the
        iterations of all rounds share ``max_iterations``; ``lam_g`` are every row's multipliers at ``x``
        (CasADi's sign, ≤ 0; 0 for the rows outside the working set). ``lam_g`` (argument): estimates of
        every row's multiplier: the first round then starts warm, and the rows they hold join the
        working set."""
        x = np.clip(np.asarray(start, dtype=float), lower, upper)
        values = self.row_values(x)
        keep = max(WORKING_ROWS, ROWS_PER_VARIABLE * self.nlp.size)
        # the rows of the first samples (a workspace's samples are space-filling in any prefix), the rows
        # of no sample, the violated rows and the closest to binding
        active = (self._row_sample < min(SPREAD_SAMPLES, self.n_samples // 8)) | (self._row_sample == self.n_samples)
        for block, n_varying in self._extreme:  # a bound's rows: those of its extreme samples, not the spread ones
            rows_of = block + n_varying * np.arange(self.n_samples)
            active[rows_of] = False
            active[rows_of[np.argsort(values[rows_of], kind="stable")[:EXTREME_SAMPLES]]] = True
        violated = np.flatnonzero(
            values < ROW_TOLERANCE
        )  # at most `keep` of them, the worst: later rounds add the rest
        active[violated[np.argsort(values[violated])[:keep]]] = True
        multipliers = None
        if lam_g is not None:
            held = np.flatnonzero(lam_g != 0)  # at most `keep` of them, of the largest multipliers
            active[held[np.argsort(lam_g[held])[:keep]]] = True
            multipliers = (np.zeros(self.nlp.size), np.asarray(lam_g, dtype=float))
        active[_closest(values, active, keep)] = True
        iterations, status = 0, "not run"
        for round_ in range(MAX_ROUNDS):
            if round_ == MAX_ROUNDS - 1:
                active[:] = True
            rows = np.flatnonzero(active)
            # a warm round usually needs few iterations; it may take half the budget even when the first ones used it
            round_options = {**options, "ipopt.max_iter": max(1, max_iterations - iterations, max_iterations // 2)}
            arguments = {"x0": x, "lbx": lower, "ubx": upper, "lbg": 0.0, "ubg": np.inf}
            if multipliers is not None:  # warm start: the previous round's multipliers, 0 for the new rows
                lam_x, lam_g = multipliers
                arguments.update(lam_x0=lam_x, lam_g0=lam_g[rows])
                round_options.update(warm_start_options())
                if self.extra_start is not None:  # the epigraph bounds of the design reached, over every sample
                    x[self.n_design :] = np.clip(
                        np.maximum(x[self.n_design :], self.extra_start(x[: self.n_design])),
                        lower[self.n_design :],
                        upper[self.n_design :],
                    )
            solver, plateau = self._solver(rows, round_options)
            result = solver(**arguments)
            stats = solver.stats()
            iterations += int(stats.get("iter_count", 0))
            status = PLATEAU_STATUS if plateau and plateau.stopped else str(stats.get("return_status", "unknown"))
            x = np.clip(np.array(result["x"]).reshape(-1), lower, upper)
            lam_g = np.zeros(self.n_rows)
            lam_g[rows] = np.array(result["lam_g"]).reshape(-1)
            multipliers = (np.array(result["lam_x"]).reshape(-1), lam_g)
            values = self.row_values(x)
            violated = ~active & (values < -ROW_TOLERANCE)
            if not violated.any() or iterations >= 2 * max_iterations or status not in CONVERGED:
                break
            added = violated.copy()
            added[_closest(values, active | violated, keep // 2)] = True
            active |= added
        assert multipliers is not None  # every round sets them (MAX_ROUNDS ≥ 1)
        return x, status, iterations, multipliers[1]


def warm_start_options() -> dict:
    """IPOPT's options for a start from a point and multipliers near the solution: the point and the
    multipliers pushed only :data:`WARM_PUSH` into the interior."""
    return {
        "ipopt.warm_start_init_point": "yes",
        **{
            f"ipopt.warm_start_{name}": WARM_PUSH
            for name in ("bound_push", "bound_frac", "slack_bound_push", "slack_bound_frac", "mult_bound_push")
        },
    }


def _closest(values: np.ndarray, taken: np.ndarray, count: int) -> np.ndarray:
    """Indices of the ``count`` smallest ``values`` not yet ``taken``."""
    free = np.flatnonzero(~taken)
    if free.size <= count:
        return free
    return free[np.argpartition(values[free], count)[:count]]
