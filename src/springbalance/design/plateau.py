r"""IPOPT's stop on a plateau of the objective, for the NLPs of helical coils (docs/model.md §6).

IPOPT stops when its scaled KKT error falls below ``tol`` (1e-8 here) or at its iteration limit. On an NLP with
helical coils it seldom reaches the tolerance: the design is degenerate along some directions (a coil's rate
traded against its anchors' lever arms; for a zero-free-length law only ``k·a·b`` counts), IPOPT regularises its
Hessian there, and the iterates slide along a valley floor where the dual infeasibility swings between 1e-6 and
1e-2 while the objective creeps. On bench_real's ur5-coils-clear (seed 0), a polish of 400 iterations had gained
0.08 % of its objective after its 60th iteration, and half of the solve's 3,710 IPOPT iterations came after such a
plateau began.

:class:`Plateau` is IPOPT's iteration callback. At iteration ``k ≥`` :data:`MIN_ITERATIONS` it stops the solve
(IPOPT's ``User_Requested_Stop``, which the solver reports as :data:`PLATEAU_STATUS`) when the iterate meets every
row of the solve within :data:`ROW_SLACK`, and so did iterate ``k - W``, and the objective fell by no more than a
fraction :data:`RELATIVE_GAIN` of itself over those :data:`WINDOW` iterations:

.. math::
    f_{k-W} - f_k \le \varepsilon\,|f_k|, \qquad W = 30,\ \varepsilon = 10^{-4}.

A plateau is not a proof that no lower objective follows: a warm-started solve may creep for some iterations, then
fall (hence no stop before :data:`MIN_ITERATIONS`). Only NLPs with helical coils stop so (:func:`stops_on_plateau`):
the ideal path (whose residual can vanish: exact balance) and the fits of ideal twins end at IPOPT's tolerance or
its iteration limit, as before.
"""

from __future__ import annotations

from typing import Any, Callable, Sequence

import casadi as ca
import numpy as np

from springbalance.springs.laws.coil import HelicalCoilSpring

#: the solver's status of a solve this callback stopped (IPOPT's own is ``User_Requested_Stop``)
PLATEAU_STATUS = "Objective_Plateau"
#: iterations over which the objective's fall is measured
WINDOW = 30
#: a fall of at most this fraction of the objective over :data:`WINDOW` iterations is a plateau
RELATIVE_GAIN = 1e-4
#: no stop before this iteration (a warm start may creep for its first iterations, then fall)
MIN_ITERATIONS = 50
#: an iterate meets a row ``g ≥ 0`` when ``g ≥ -ROW_SLACK`` (the rows' scaled units)
ROW_SLACK = 1e-6


def stops_on_plateau(problem: Any) -> bool:
    """Whether IPOPT's solves of ``problem`` stop on a plateau of the objective: when a spring is a helical coil."""
    return any(isinstance(spring, HelicalCoilSpring) for spring in problem.springs)


class Plateau(ca.Callback):
    """IPOPT's iteration callback (CasADi's ``iteration_callback``) that stops a solve on a plateau of its
    objective (see the module docstring). One per solver: it keeps the objective of each iteration so far
    (NaN where the iterate broke a row of the solve); :attr:`stopped` says whether it stopped the solve.

    ``every_row_met``: whether an iterate (IPOPT's ``x``) meets the rows the solve does not see (those outside a
    working set, :mod:`~springbalance.design.structured_nlp`). At the first plateau where it does not, the callback
    stops no more (:attr:`gave_up`): the solve goes on as without it, to IPOPT's tolerance or its limit, where the
    working set grows. Stopped on a plateau, a round of a small budget would have to pull the design back into
    rows it breaks: on the Panda example at seed 1 such rounds ended on their limit, infeasible, and the multi-start
    kept a poorer design (4.75 N·m instead of 2.89)."""

    def __init__(self, n_x: int, n_g: int, every_row_met: Callable[[np.ndarray], bool] | None = None) -> None:
        ca.Callback.__init__(self)
        self.n_x, self.n_g, self.every_row_met = n_x, n_g, every_row_met
        self.objectives: list[float] = []
        self.stopped = self.gave_up = False
        names = ca.nlpsol_out()
        self._x, self._f, self._g = names.index("x"), names.index("f"), names.index("g")
        self.construct("plateau", {})

    def get_n_in(self) -> int:
        return ca.nlpsol_n_out()

    def get_n_out(self) -> int:
        return 1

    def get_name_in(self, i: int) -> str:
        return ca.nlpsol_out(i)

    def get_name_out(self, i: int) -> str:
        return "stop"

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        name = ca.nlpsol_out(i)
        sizes = {"f": 1, "x": self.n_x, "lam_x": self.n_x, "g": self.n_g, "lam_g": self.n_g}
        return ca.Sparsity.dense(sizes[name], 1) if name in sizes else ca.Sparsity(0, 0)

    def eval(self, arg: Sequence[ca.DM]) -> list:
        """One iteration: ``[1]`` stops IPOPT, ``[0]`` lets it go on."""
        objective = float(arg[self._f])
        rows = np.asarray(arg[self._g], dtype=float).reshape(-1)
        feasible = rows.size == 0 or float(rows.min()) >= -ROW_SLACK
        self.objectives.append(objective if feasible else float("nan"))
        k = len(self.objectives) - 1
        if self.gave_up or k < max(MIN_ITERATIONS, WINDOW) or not feasible:
            return [0]
        before = self.objectives[k - WINDOW]
        if not (np.isfinite(before) and before - objective <= RELATIVE_GAIN * abs(objective)):
            return [0]
        if self.every_row_met is not None and not self.every_row_met(np.asarray(arg[self._x], dtype=float).reshape(-1)):
            self.gave_up = True
            return [0]
        self.stopped = True
        return [1]
