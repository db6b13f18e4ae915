"""One fitting round of the clearance loop (:mod:`springbalance.design.clearance_fit`), what the loop does
when a round stops infeasible, the rounds that tighten a fitted design (:class:`Tightening`) and the fit's record
(:func:`finished`).

A round is a warm start of the problem with its linearised rows. When IPOPT stops it infeasible, its
iterate breaks some row. When that is a rule of the design (a bound, a coil slack, a fatigue bound), the
loop may rebuild the rows there and try again, but it never returns such a design. When the iterate is a
design of the problem (within its bounds, every rule met) that misses only the round's linearised rows
(clearance cuts, mounting planes), the loop goes on from it however many such rounds come
(:data:`OUTSIDE_NOTE`), but that design is not the fit's either, even when clear: the next round
rebuilds the rows there and must meet them (counted with the others, such rounds stopped the UR5 with
anchors on its links after two rounds, its springs still through the links; taken as converged when
clear, they fitted the UR5 example's ideal twin at 70× its objective). After :data:`INFEASIBLE_ROUNDS`
rounds in a row that broke a rule, or when the loop ends on one, it falls back to the last design that met its rows (:func:`fell_back`); that one was
not clear of the arm (else the loop would have stopped there), so the fit is not converged, and
:func:`~springbalance.design.clearance_starts.fit_from_starts` fits the next ranked designs of the
multi-start (:func:`fall_back`), as it does after a fit that ran out of rounds. It fits the next one also when
every fit converged only after its rounds moved the design: a design clear as it stands may end better.
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import Any, Callable, Sequence

import numpy as np

from springbalance.design.clearance import FitRecord, LinearRows, stacked_rows
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import FEASIBILITY_TOLERANCE, Solution, solve_problem
from springbalance.errors import SolverError

#: Fitting rounds in a row that may stop infeasible before the loop gives up on its start.
INFEASIBLE_ROUNDS = 2
#: Designs of the multi-start fitted beyond :attr:`~springbalance.design.clearance.Clearance.starts` when no
#: fit converged (the next ranked ones, best first); one when every fit converged only after moving its design
#: (:func:`fall_back`).
FALLBACK_STARTS = 2
#: A fit that ends within this fraction of the multi-start's best objective (before any fit) is as good as a fit gets:
#: no further design is fitted for a better one (:func:`fall_back`).
AT_BEST = 1e-2
#: The note a fitting round that stopped infeasible leaves in the solution's status.
INFEASIBLE_NOTE = "a fitting round stopped infeasible"
#: The note of a round IPOPT stopped infeasible whose iterate breaks only the round's linearised rows.
OUTSIDE_NOTE = "a fitting round ended outside its linearised rows"
#: How far [fraction of its range] a variable may lie outside its bounds in a design that :func:`meets_rules`.
BOUND_SLACK = 1e-6
#: How far [fraction of its range] a fitting round may move each design variable (:func:`trust_rows`).
TRUST_REGION = 0.1
#: The length [m] that scales a trust row: a move of the whole range counts as this far.
TRUST_LENGTH = 0.1
#: Most rounds after a fitted design with the rows linearised again there (:class:`Tightening`).
TIGHTEN_ROUNDS = 4
#: A tightening round goes on only while the one before lowered the objective by more than this fraction.
TIGHTEN_GAIN = 1e-3


def solve_round(
    problem: DesignProblem, x: np.ndarray, solution: Solution, solve_options: dict[str, Any], trusted: bool = False
) -> tuple[Solution | None, str]:
    """One round (:func:`_solved_round`); ``trusted``: first inside the round's trust region (:func:`trust_rows`),
    and when it stops short of its rows there, again without it."""
    if trusted:
        inside = problem.with_linear_rows(stacked_rows(problem.linear_rows, trust_rows(problem, x)))
        resolved, note = _solved_round(inside, x, solution, solve_options)
        if resolved is not None and not note:
            return resolved, note
    return _solved_round(problem, x, solution, solve_options)


def trust_rows(problem: DesignProblem, x: np.ndarray) -> LinearRows | None:
    r"""The round's trust region: every design variable ``x_i`` with a finite range ``R_i`` (auxiliary variables
    aside) within :data:`TRUST_REGION` ``R_i`` of where the round starts,

    .. math:: \ell\,(x_i - x_{k,i} + \rho R_i)/R_i \ge 0, \qquad \ell\,(x_{k,i} + \rho R_i - x_i)/R_i \ge 0,

    rows in [m] through ``ℓ`` = :data:`TRUST_LENGTH`. The cuts of a round are linearised where it starts and say
    nothing of the arm far from there; and the objective is degenerate along whole families of designs (a
    zero-free-length spring's ``k·a·b``). Without a trust region a round's solve may slide along such a family
    far from the cuts' poses, into links that no cut watches, and the next round finds new violations there:
    the UR5's ideal twin fitted 5 mm clear of its links moved its stiffnesses by up to 2.8·10⁵ N/m a round,
    gathered 94 cuts in 12 rounds and did not converge (25 s); within 10 % of each range it fitted in one
    round (2 s) at the same objective. The loop uses it when its rounds without one do not converge
    (:func:`~springbalance.design.clearance_fit.fit_to_arm`)."""
    lower, upper = (np.asarray(bound, dtype=float) for bound in problem.variables.bounds())
    span = upper - lower
    auxiliary = set(problem.model.auxiliary_names)
    names = list(problem.variables.names)
    free = [i for i, name in enumerate(names) if np.isfinite(span[i]) and span[i] > 0 and name not in auxiliary]
    if not free:
        return None
    x = np.asarray(x, dtype=float)
    gain = TRUST_LENGTH / span[free]
    reach = TRUST_REGION * span[free]
    matrix = np.vstack([np.diag(gain), -np.diag(gain)])
    offset = np.concatenate([gain * (reach - x[free]), gain * (reach + x[free])])
    labels = [f"{names[i]} within its trust region ({side})" for side in ("low", "high") for i in free]
    return LinearRows([names[i] for i in free], matrix, offset, labels)


def _solved_round(
    problem: DesignProblem, x: np.ndarray, solution: Solution, solve_options: dict[str, Any]
) -> tuple[Solution | None, str]:
    """One warm start of ``problem`` (with this round's rows) from ``x``, and ``""`` when it met them. When the
    linearised rows cannot all be met from there, the least violating iterate (the next round may rebuild the
    rows there) and the note saying so: :data:`OUTSIDE_NOTE` when that iterate breaks none of the design's own
    rules (:func:`meets_rules`), only this round's linearised rows, else :data:`INFEASIBLE_NOTE`. None when the
    solver returned no iterate at all."""
    try:
        found = solve_problem(problem, starts=1, initial=x, progress=False, **solve_options)
        # the solution keeps the multi-start's records (design.json's and the report's "multi-start" line are
        # about them); the round is in the fit's record
        return dataclasses.replace(found, starts=solution.starts, method=solution.method, seed=solution.seed), ""
    except SolverError as error:
        if not error.starts:
            return None, ""
        least = min(error.starts, key=lambda record: record.max_violation)
        note = f"{OUTSIDE_NOTE if meets_rules(problem, least.x) else INFEASIBLE_NOTE} ({least.status})"
        return Solution(least.x, solution.starts, solution.method, solution.seed, f"{solution.status}; {note}"), note


def meets_rules(problem: DesignProblem, x: np.ndarray) -> bool:
    """Whether ``x`` [physical units] is a design of ``problem`` apart from its linear rows: every variable within
    its bounds (to :data:`BOUND_SLACK` of its range, IPOPT's own relaxation of the bounds) and every constraint
    row (coil rules, tension, fatigue) within :data:`~springbalance.design.solvers.FEASIBILITY_TOLERANCE` [m or N]."""
    x = np.asarray(x, dtype=float)
    lower, upper = (np.asarray(bound, dtype=float) for bound in problem.variables.bounds())
    slack = BOUND_SLACK * (upper - lower)
    if not np.all(np.isfinite(x)) or np.any(x < lower - slack) or np.any(x > upper + slack):
        return False
    return bool(problem.evaluate(x).max_violation <= FEASIBILITY_TOLERANCE)


def fell_back(
    x: np.ndarray,
    solution: Solution,
    problem: DesignProblem,
    closest: dict[str, float],
    mounts: dict[str, float],
    rounds: int,
    note: str,
) -> tuple[np.ndarray, Solution, DesignProblem, dict[str, float], dict[str, float]]:
    """The last design that met its rows (found after ``rounds`` rounds, with the problem of those rows and
    its check: closest distances [m], mount errors [m]), its status saying a later round stopped (``note``)."""
    status = f"{solution.status}; {note}; fell back to the design of round {rounds}"
    return x, Solution(x, solution.starts, solution.method, solution.seed, status), problem, closest, mounts


def fall_back(
    fits: Sequence[tuple[Solution, FitRecord, Any]], extra: int, accepted: Callable[[Any], bool] | None = None
) -> bool:
    """Whether to fit one more (the ``extra``-th beyond ``Clearance.starts``) ranked design: while no fit
    converged (a fitting round stopped infeasible, or the rounds ran out) and fewer than :data:`FALLBACK_STARTS`
    were added (bench_real's ur5-coils-clear at seed 2: the coils' fit ran out of its 24 rounds and of 24 more
    inside trust regions, and the design failed as overlapping; the next ranked design fitted in one round, and the
    design passed at 0.985 N·m); while every fit that converged did so to a design that is not ``accepted``
    (default: every converged design is; :func:`~springbalance.design.clearance_starts.fit_from_starts` refuses one that carries a weighted
    joint worse than the bare arm); or, once, when every accepted fit had to move its design (a round or more):
    the next ranked design may be clear as it stands and end better than a design the rounds moved (the Panda
    example: its best start fitted in 4 rounds at 3.17 N·m, its second clear at 2.89), unless an accepted fit ends
    within :data:`AT_BEST` of the best design's objective before any fit: a fit adds rows to the problem, so no
    fitted design lies much below the multi-start's best (ur5-coils-clear's ideal twin at seed 4 fitted its best
    design in 10 rounds to 0.08731 N·m, below its 0.093, then its second in 21 rounds, 118 s, to the same)."""
    if extra >= FALLBACK_STARTS:
        return False
    converged = [fit for fit in fits if fit[1].converged]
    good = [fit for fit in converged if accepted is None or accepted(fit)]
    if good:
        best_before = min(fit[1].objective_before for fit in fits)
        at_best = any(fit[1].objective <= (1.0 + AT_BEST) * best_before for fit in good)
        return extra == 0 and not at_best and all(fit[1].rounds > 0 for fit in good)
    return True


@dataclasses.dataclass
class Tightening:
    """Rounds after the loop's first fitted design (clear of the arm, its mountings met, its rows met), the rows
    linearised again at that design, while each lowers the objective by more than :data:`TIGHTEN_GAIN`; at most
    :data:`TIGHTEN_ROUNDS`. The design of lowest objective among the fitted ones is the fit's.

    A round's rows are linearised where it starts, so a fitted design is the optimum of rows taken at the design
    before it, not of the clearance itself. For convex shapes the linearised distance bounds the distance from below
    (the rows are conservative), so a fitted design meets the rows taken at itself, and a round from there can only
    lower the objective: the rounds are a sequential convex programme, which stops at a point where the clearance's
    own first-order conditions hold. On bench_real's ur5-mounted-clear (ideal springs on the UR5's link surfaces)
    seed 3 fitted at 0.819 N·m without them and at 0.672 with them (elbow 83.87 → 88.71 %). The solve tightens
    the fits of problems without free coils only (:func:`springbalance.pipeline.steps.tightened`); so the ideal twin
    of coils (:mod:`springbalance.design.coil_start`) is not tightened either: a twin closer to its own optimum was a
    worse start for the coils (example-ur5 at seed 4: 4.82 N·m and a joint made worse, against 4.32)."""

    rounds: int = 0
    best: tuple | None = None  # (x, solution, problem, closest, mounts, rounds) of the lowest objective
    objective: float = math.inf

    def goes_on(self, objective: float, fitted: tuple, rounds: int, limit: int) -> bool:
        """Record the fitted design ``fitted`` (of ``objective``, after ``rounds`` of at most ``limit``); whether a
        tightening round follows."""
        improved = objective < self.objective * (1.0 - TIGHTEN_GAIN)
        if objective < self.objective:
            self.objective, self.best = objective, fitted
        if improved and self.rounds < TIGHTEN_ROUNDS and rounds < limit:
            self.rounds += 1
            return True
        return False


def finished(
    problem: DesignProblem,
    solution: Solution,
    x: np.ndarray,
    rounds: int,
    converged: bool,
    before: float,
    closest: dict[str, float],
    mounts: dict[str, float],
    poses: int,
    clock: float,
) -> tuple[Solution, FitRecord, DesignProblem]:
    """The fit's solution at ``x``, its :class:`FitRecord` (``poses``: how many were checked; ``clock``: when the
    loop started) and ``problem``."""
    objective = problem.objective_at(x)
    record = FitRecord(
        rounds,
        len(problem.linear_rows) if problem.linear_rows is not None else 0,
        converged,
        before,
        float(objective),
        {k: float(v) for k, v in closest.items()},
        {k: float(v) for k, v in mounts.items()},
        poses,
        time.perf_counter() - clock,
    )
    status = f"{solution.status}; fitted to the arm in {rounds} round(s)" + (
        "" if converged else " (NOT converged: see the clearance check)"
    )
    return Solution(x, solution.starts, solution.method, solution.seed, status), record, problem
