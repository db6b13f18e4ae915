"""The loop that verifies a design where it was not optimised, and re-solves it where a rule fails.

:func:`verify_and_resolve` checks the design at unseen poses (:func:`~springbalance.design.verification.check_design`).
When a rule fails there (and the mode is ``"resolve"``), the worst poses join the problem's samples
(:meth:`~springbalance.design.problem.DesignProblem.with_samples`), the clearance contacts below the margin
join its linear rows as cuts (:mod:`springbalance.design.clearance_rows`, as the fit makes them; with them the
closest approach near each, found by a descent over the joint coordinates, as the fit searches), and the
problem is solved again from the design (one warm start, the rounded wires held); then the design is
verified again at a fresh set of unseen poses (the next round's seed), up to :data:`VERIFY_ROUNDS` re-solves.
Where no re-solve meets the cuts at once, the design is fitted to the arm again from where it is (:func:`_refit`).
This is the clearance fit's pattern (:mod:`springbalance.design.clearance_fit`) for every rule.

The design returned belongs to the problem as given, with the cuts added to its linear rows: the poses
added are samples of the re-solves only, so the objective and the metrics stay those of the user's
workspace.
"""

from __future__ import annotations

import time
from typing import Any, Sequence

import numpy as np

from springbalance.design.clearance import LinearRows, stacked_rows
from springbalance.design.clearance_fit import Key, Nearest, _Checker, fit_to_arm
from springbalance.design.clearance_rows import _rows
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution, solve_problem
from springbalance.design.verification import check_design
from springbalance.design.verification_record import VerificationRecord
from springbalance.errors import InputError, SolverError

#: most re-solves of the loop
VERIFY_ROUNDS = 3
#: starts of a re-solve whose warm start finds no feasible design (the first one is the design)
RESCUE_STARTS = 4
#: what a failed verification does: ``"resolve"`` (add the poses, solve again), ``"report"`` (report
#: only) or ``"off"`` (no verification)
MODES = ("resolve", "report", "off")


def check_mode(mode: object) -> str:
    """``mode`` when it is one of :data:`MODES`; InputError naming it otherwise."""
    if mode not in MODES:
        raise InputError(f"unknown verify mode {mode!r}; valid: {', '.join(MODES)}")
    assert isinstance(mode, str)  # one of MODES
    return mode


def verify_and_resolve(
    problem: DesignProblem,
    solution: Solution,
    mode: str = "resolve",
    fixed: Sequence[str] = (),
    held: bool = False,
    **solve_options: Any,
) -> tuple[Solution, VerificationRecord, DesignProblem]:
    """Verify ``solution`` of ``problem`` at unseen poses; in mode ``"resolve"``, re-solve where a rule fails.

    ``fixed``: design variables held in the re-solves (the wires rounded to standard sizes); ``held``: the design
    was solved again with every weighted joint held within the bare arm's peak
    (:func:`~springbalance.design.joint_hold.held_within_bare_arm`), and the re-solves keep those rows
    (``no_joint_worse``), else a re-solve that meets a rule at a new pose may load the joint again: the two-link
    arm of tests/design/test_verification_hold.py ended ``worse_joint`` after three re-solves of its held design.
    The rules are checked on ``problem`` as given. ``solve_options`` go to
    :func:`~springbalance.design.solvers.solve_problem`. Returns the solution, its
    :class:`~springbalance.design.verification_record.VerificationRecord` and ``problem`` (with the
    clearance cuts the loop added to its linear rows, if any).
    """
    clock = time.perf_counter()
    mode = check_mode(mode)
    checker = _Checker(problem, problem.clearance) if problem.clearance is not None else None
    x = np.array(solution.x, dtype=float)
    added = np.empty((0, problem.mechanism.nv))
    watched: set[Key] = set()
    result_problem, rounds = problem, 0
    solved = problem  # what the re-solves solve: with the hold's rows when ``held`` (built at the first re-solve)
    while True:
        check = check_design(problem, x, rounds, checker, mode)
        if check.record.passed or mode != "resolve" or rounds >= VERIFY_ROUNDS:
            break
        added = np.vstack([added, check.poses])
        watched.update(check.contacts)
        if checker is not None and check.contacts:
            watched.update(_closest_nearby(checker, x, check.contacts))
        rows = problem.linear_rows
        if checker is not None and watched:
            object_cuts, spring_cuts = checker.cuts(x, watched)
            rows = stacked_rows(rows, _rows(problem, x, object_cuts, spring_cuts, None))
        if held and solved is problem:
            solved = problem.with_springs(problem.springs, no_joint_worse=True)
        extended = (solved.with_samples(added) if added.shape[0] else solved).with_linear_rows(rows)
        resolved = _round(extended, x, solution, fixed, solve_options)
        if resolved is None and checker is not None and watched:
            resolved, rows = _refit(solved, solution, checker, fixed, solve_options)
        if resolved is None:
            break
        solution, x, rounds = resolved, np.array(resolved.x, dtype=float), rounds + 1
        result_problem = problem.with_linear_rows(rows)
    record = check.record
    record.rounds, record.added_poses, record.seconds = rounds, int(added.shape[0]), time.perf_counter() - clock
    if rounds:
        verdict = "verified" if record.passed else "NOT verified"
        solution = Solution(
            x,
            solution.starts,
            solution.method,
            solution.seed,
            f"{solution.status}; {verdict} at unseen poses after {rounds} re-solve(s)",
            solution.multipliers,
        )
    return solution, record, result_problem


def _closest_nearby(checker: _Checker, x: np.ndarray, contacts: Sequence[Key]) -> dict[Key, float]:
    """The closest approach near each of the ``contacts`` below the margin, by a bounded descent over the joint
    coordinates from its pose (:meth:`~springbalance.design.clearance_fit._Checker.descend`, as the fit searches
    between its samples): contacts of the checker's pose set 2 → distance [m], where below the margin too. The
    unseen poses are samples too, and cuts at them alone leave the poses between them below the margin: on
    bench_real's ur5-coils-clear (seed 0) each of three re-solves met its cuts and the next fresh set of poses
    found another contact a fraction of a millimetre below the margin."""
    nearest: Nearest = {}
    for key in contacts:
        nearest.setdefault(key[:4], []).append((-np.inf, key[4], key[5]))
    below, _ = checker.descend(x, nearest)
    return below


def _refit(
    problem: DesignProblem, solution: Solution, checker: _Checker, fixed: Sequence[str], solve_options: dict[str, Any]
) -> tuple[Solution | None, LinearRows | None]:
    """Where no re-solve from the design meets the cuts at once: the clearance fit again from the design
    (:func:`~springbalance.design.clearance_fit.fit_to_arm`), its rows rebuilt from there, ``fixed`` held, with the
    closest approaches this loop found watched in every round (``checker``'s pose set 2); the fitted design and
    its rows, or ``(None, None)`` when that fit does not converge. On bench_real's ur5-mounted-clear (seed 0) the
    fit had converged at its own poses while a spring passed 11.9 mm inside a link at an unseen pose, and no
    re-solve with the cut there was feasible (1.116 N·m, not verified); fitted again, the design was verified
    at 0.5467 N·m."""
    options = {**solve_options, "fixed": list(fixed)}
    fitted, record, fitted_problem = fit_to_arm(problem.with_linear_rows(None), solution, checker=checker, **options)
    if not record.converged:
        return None, None
    return fitted, fitted_problem.linear_rows


def _round(
    problem: DesignProblem, x: np.ndarray, solution: Solution, fixed: Sequence[str], solve_options: dict[str, Any]
) -> Solution | None:
    """One warm start of ``problem`` (with the added samples and cuts) from ``x``, ``fixed`` held; when it finds
    no feasible design (a pose far outside the design's rules moves it far), :data:`RESCUE_STARTS` starts from
    ``x`` and Sobol points, ``fixed`` held at ``x``'s values; None when they find none either (the design
    before stays)."""
    for starts in (1, RESCUE_STARTS):
        try:
            found = solve_problem(problem, starts=starts, initial=x, fixed=list(fixed), progress=False, **solve_options)
            break
        except SolverError:
            continue
    else:
        return None
    # its multipliers belong to the extended problem's rows, not to the problem's: none are kept
    return Solution(found.x, solution.starts, solution.method, solution.seed, solution.status)
