"""IPOPT for one start (:class:`IpoptStarts`): the general NLP of
:meth:`~springbalance.design.problem.DesignProblem.build` with exact derivatives, used for the ``peak``,
``joint_peaks`` and ``energy`` objectives (epigraph form), warm-started from the rms least-squares solution.
A lexicographic objective (``peak_then_joints``) takes two IPOPT phases per start: its first phase (``peak``)
to ``T*``, then its own NLP with the epigraph variables bounded by ``T*·(1 + slack)``.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from springbalance.design.evaluation import Evaluation, Nlp
from springbalance.design.objectives import Objective
from springbalance.design.solvers.records import EPIGRAPH_TOLERANCE, FEASIBILITY_TOLERANCE, Problem
from springbalance.design.structured_nlp import NotStructured, StructuredNlp, warm_start_options


class _StructuredIpopt:
    """IPOPT through :class:`~springbalance.design.structured_nlp.StructuredNlp` (working set of rows)."""

    def __init__(self, structured: StructuredNlp, options: dict[str, Any]) -> None:
        self.structured, self.nlp, self.options = structured, structured.nlp, options

    def solve(
        self,
        start: np.ndarray,
        lower: np.ndarray,
        upper: np.ndarray,
        max_iterations: int,
        lam_g: np.ndarray | None = None,
    ) -> tuple[np.ndarray, str, int, np.ndarray]:
        return self.structured.solve(start, lower, upper, self.options, max_iterations, lam_g)


class _PlainIpopt:
    """IPOPT on the plain NLP, every row, CasADi's derivatives (for an NLP without the per-sample structure)."""

    def __init__(self, nlp: Nlp, options: dict[str, Any]) -> None:
        self.nlp, self.options = nlp, options
        self._solvers: dict[tuple[int, bool], ca.Function] = {}

    def solve(
        self,
        start: np.ndarray,
        lower: np.ndarray,
        upper: np.ndarray,
        max_iterations: int,
        lam_g: np.ndarray | None = None,
    ) -> tuple[np.ndarray, str, int, np.ndarray]:
        warm = lam_g is not None
        solver = self._solvers.get((max_iterations, warm))
        if solver is None:
            nlp = self.nlp
            solver = self._solvers[max_iterations, warm] = ca.nlpsol(
                "springbalance",
                "ipopt",
                {"x": nlp.z, "f": nlp.cost, "g": nlp.rows},
                {**self.options, "ipopt.max_iter": int(max_iterations), **(warm_start_options() if warm else {})},
            )
        arguments: dict[str, np.ndarray] = {"lam_g0": lam_g} if lam_g is not None else {}  # (lam_g given: warm)
        solution = solver(x0=start, lbx=lower, ubx=upper, lbg=0.0, ubg=np.inf, **arguments)
        stats = solver.stats()
        return (
            np.array(solution["x"]).reshape(-1),
            str(stats.get("return_status", "unknown")),
            int(stats.get("iter_count", 0)),
            np.array(solution["lam_g"]).reshape(-1),
        )


class IpoptStarts:
    """The IPOPT part of :class:`~springbalance.design.solvers.multistart._MultiStartSolver` (a mixin): it
    reads ``problem``, ``fixed``, ``max_iterations``, ``tolerance`` and keeps ``_ipopt`` and ``_first`` (the
    NLP solvers of the objective and of a lexicographic objective's first phase)."""

    problem: Problem
    fixed: np.ndarray
    max_iterations: int
    tolerance: float
    _ipopt: _StructuredIpopt | _PlainIpopt | None
    _first: _StructuredIpopt | _PlainIpopt | None

    def _nlpsol(self, objective: Objective | None = None) -> _StructuredIpopt | _PlainIpopt:
        """IPOPT on the problem's NLP (of ``objective``, default its own): with derivatives from the
        per-sample structure on a working set of rows (:mod:`~springbalance.design.structured_nlp`), or
        CasADi's own of the plain NLP when it lacks that structure."""
        options = {
            "print_time": False,
            "ipopt.print_level": 0,
            "ipopt.sb": "yes",
            "ipopt.tol": min(self.tolerance, 1e-8),
            "ipopt.acceptable_tol": 1e-8,
            "ipopt.mu_strategy": "adaptive",
        }
        problem = self.problem
        key = None if objective is None else objective.name
        cached = problem.nlp_cache.get(key)
        if cached is None or cached[0] is not problem.linear_rows:  # new linear rows: a new NLP replaces it
            nlp: Nlp | StructuredNlp
            try:
                nlp = StructuredNlp(problem, objective)
            except NotStructured:
                nlp = problem.build(objective)
            cached = problem.nlp_cache[key] = (problem.linear_rows, nlp)
        nlp = cached[1]
        return _StructuredIpopt(nlp, options) if isinstance(nlp, StructuredNlp) else _PlainIpopt(nlp, options)

    def _ipopt_solvers(self) -> tuple[_StructuredIpopt | _PlainIpopt, _StructuredIpopt | _PlainIpopt | None]:
        """Build the NLP solvers once: the objective's, and a lexicographic objective's first phase
        (None for a one-phase objective); returns both."""
        if self._ipopt is None:
            first_phase = self.problem.objective.first_phase
            if first_phase is not None:
                self._first = self._nlpsol(first_phase)
            self._ipopt = self._nlpsol()
        return self._ipopt, self._first

    def _ipopt_solve(
        self,
        z: np.ndarray,
        evaluation: Evaluation,
        multipliers: np.ndarray | None = None,
        lam_g: np.ndarray | None = None,
    ) -> tuple[np.ndarray, str, int, np.ndarray | None]:
        """IPOPT from ``z``; returns ``(z, status, iterations, lam_g)``, ``lam_g``: IPOPT's multipliers of the
        NLP rows at ``z`` (None for a lexicographic objective, whose last NLP has its phase's bounds).

        IPOPT starts warm from ``multipliers``, the least-squares estimates of the constraint rows'
        multipliers when the objective is the least-squares cost itself, or from ``lam_g``, multipliers
        of the NLP rows (CasADi's sign)."""
        problem = self.problem
        solver, first_solver = self._ipopt_solvers()
        first_phase = problem.objective.first_phase
        if first_phase is None:
            return self._ipopt_run(solver, z, evaluation, multipliers=multipliers, lam_g=lam_g)
        assert first_solver is not None  # built with the objective's, for its first phase
        # lexicographic: the first phase's optimum T*, then the objective's own NLP with its
        # epigraph variables bounded by T*·(1 + slack)
        z1, status1, iterations1, _ = self._ipopt_run(first_solver, z, evaluation)
        first = problem.evaluate(problem.scale(z1))
        weighted = first.tau * problem.weights
        bound = problem.objective.phase_two_bound(
            first_phase.value(weighted, first.potential, problem.path_steps), problem.torque_scale
        )
        upper = solver.nlp.upper.copy()
        upper[solver.nlp.n_design :] = bound
        z2, status2, iterations2, _ = self._ipopt_run(solver, z1, first, upper=upper)
        second = problem.evaluate(problem.scale(z2))
        value = problem.objective.value(second.tau * problem.weights, second.potential, problem.path_steps)
        kept = (
            second.max_violation <= max(FEASIBILITY_TOLERANCE, first.max_violation)
            and value <= (bound + EPIGRAPH_TOLERANCE) * problem.torque_scale
        )
        status = f"{status1}, then {status2.removeprefix('ipopt: ')}{'' if kept else ' (not kept)'}"
        return (z2 if kept else z1), status, iterations1 + iterations2, None

    def _ipopt_run(
        self,
        ipopt: _StructuredIpopt | _PlainIpopt,
        z: np.ndarray,
        evaluation: Evaluation,
        upper: np.ndarray | None = None,
        multipliers: np.ndarray | None = None,
        lam_g: np.ndarray | None = None,
    ) -> tuple[np.ndarray, str, int, np.ndarray]:
        problem, nlp = self.problem, ipopt.nlp
        start = z
        if multipliers is not None:  # CasADi's sign: a row held at its lower bound has λ ≤ 0
            lam_g = -problem.nlp_row_multipliers(multipliers, nlp.n_rows)
        if nlp.size > nlp.n_design:
            assert nlp.extra_start is not None  # an NLP with extra (epigraph) variables has their start
            extra = nlp.extra_start(evaluation.tau * problem.weights)
            if upper is not None:
                extra = np.minimum(extra, upper[nlp.n_design :])
            start = np.concatenate([z, extra])
        lower, upper = nlp.lower.copy(), (nlp.upper if upper is None else upper).copy()
        lower[: nlp.n_design][self.fixed] = upper[: nlp.n_design][self.fixed] = z[self.fixed]
        x, status, iterations, lam_g = ipopt.solve(start, lower, upper, self.max_iterations, lam_g)
        return np.clip(x[: nlp.n_design], 0.0, 1.0), f"ipopt: {status}", iterations, lam_g
