r"""Solvers for a :class:`~springbalance.design.problem.DesignProblem`, with multi-start.

Backends:

- ``least_squares``: for objectives with least-squares structure (``rms``,
  ``pe_variance``) one per-sample CasADi function of the scaled variables gives the residual
  rows and their exact Jacobian; compiled to C when a compiler is available (the library is
  cached on disk, :mod:`~springbalance.design.compile_cache`) and evaluated over blocks of
  samples straight into NumPy buffers, where ``JᵀJ`` and ``Jᵀr`` are summed. SciPy's bounded
  trust-region-reflective method then works on an equivalent *compressed* residual of n+1
  rows (n ≈ 30 variables, while the residual has N·nv ≈ 25,000 rows), see
  :meth:`~springbalance.design.solvers.least_squares.LeastSquaresStarts._trust_region`. Practical constraints (tension, stretch, force,
  length) enter through an augmented Lagrangian: penalty rows ``max(0, λ - μ c)/√μ`` join
  the residual and the multipliers are updated between runs.
- ``ipopt``: the general NLP of :meth:`DesignProblem.build` with exact derivatives from
  CasADi; used for the ``peak``, ``joint_peaks`` and ``energy`` objectives (epigraph form),
  warm-started from the rms least-squares solution. A lexicographic objective
  (``peak_then_joints``) takes two IPOPT phases per start: its first phase (``peak``) to ``T*``,
  then its own NLP with the epigraph variables bounded by ``T*·(1 + slack)``.

``auto`` chains them: least squares first (on the rms objective when the objective has no
least-squares form), then IPOPT only when the objective needs it or a constraint is still
violated.

Every start is prepared the same way: free lengths are moved into the interval the
start's spring lengths allow (``max L/ρ ≤ l0 ≤ min L``), and the variables the torque is
linear in (stiffness, initial tension) are set to their bounded linear least-squares
optimum for the start's geometry (kept ≥ 10 % into their range so that no spring starts at
``k = 0``, where its anchors would have no gradient). Each start then runs with the
iteration budget, and the starts within 25 % of the best that stopped on the budget are
continued with a larger one ("screen, then polish"), from where they stopped: a start IPOPT
stopped goes on from its last iterate and multipliers (:meth:`~springbalance.design.solvers.multistart._MultiStartSolver._warm`, which also
starts a re-solve of a nearby problem, ``solve_problem(multipliers=...)``). The best feasible start wins; for a
lexicographic objective, the one with the lowest tiebreak among those within ``slack`` of the best value.

Starts are independent: with ``workers`` > 1 the starts (and then the polish runs) go to a pool of
worker processes forked from this one, which inherit the problem and its compiled residual (no
pickling, no recompilation). Each start computes exactly what it computes alone, so the result is
bit for bit the sequential one. Without ``workers``, :func:`default_workers` decides.

The modules, one concept each: :mod:`~springbalance.design.solvers.records` (:class:`StartRecord`,
:class:`Solution`, the tolerances), :mod:`~springbalance.design.solvers.starts` (Sobol start points),
:mod:`~springbalance.design.solvers.pool` (worker processes), :mod:`~springbalance.design.solvers.forked` (tasks
that decide the next one's need, run ahead on forked workers: the clearance fits), :mod:`~springbalance.design.solvers.multistart`
(:func:`solve_problem`: the multi-start with polish), :mod:`~springbalance.design.solvers.residuals` and
:mod:`~springbalance.design.solvers.least_squares` (augmented-Lagrangian least squares, :func:`refine`),
:mod:`~springbalance.design.solvers.ipopt` (IPOPT). This package re-exports their public names.
"""

from __future__ import annotations

from springbalance.deprecation import moved_names
from springbalance.design.solvers import multistart, pool, residuals
from springbalance.design.solvers.least_squares import refine
from springbalance.design.solvers.multistart import solve_problem
from springbalance.design.solvers.pool import (
    POOL_MIN_SECONDS,
    WORKERS_ENV,
    check_workers,
    default_workers,
    workers_default,
)
from springbalance.design.solvers.records import (
    EPIGRAPH_TOLERANCE,
    FEASIBILITY_TOLERANCE,
    METHODS,
    Solution,
    StartRecord,
)
from springbalance.design.solvers.starts import start_points

__all__ = [
    "EPIGRAPH_TOLERANCE",
    "FEASIBILITY_TOLERANCE",
    "METHODS",
    "POOL_MIN_SECONDS",
    "WORKERS_ENV",
    "Solution",
    "StartRecord",
    "check_workers",
    "default_workers",
    "refine",
    "solve_problem",
    "start_points",
    "workers_default",
]

#: private names this module had before it became a package → the module that holds them now
_MOVED = {
    "_LeastSquaresResiduals": "residuals",
    "_MultiStartSolver": "multistart",
    "_StartRunner": "pool",
    "_pool_workers": "pool",
}


__getattr__ = moved_names(
    __name__,
    {
        name: ({"residuals": residuals, "multistart": multistart, "pool": pool}[module], name)
        for name, module in _MOVED.items()
    },
)
