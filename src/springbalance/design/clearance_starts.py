"""Which designs of the multi-start the clearance loop fits (:func:`fit_from_starts`), side by side.

The loop (:func:`~springbalance.design.clearance_fit.fit_to_arm`) fits the multi-start's best design; whether
the next ranked ones are fitted too depends on how the fits before them ended
(:func:`~springbalance.design.clearance_round.fall_back`). Each fit is a chain of single-start solves, one
core's work, so the fits run on the solve's worker processes, the next one started before its need is known
(:func:`~springbalance.design.solvers.forked.run_in_order`): the same fits, bit for bit, as one after the other.
Of several fits, the one kept is the best that also holds where the verification will look
(:func:`held_at_unseen_poses`). A fit of ideal springs starts from a fit of the same springs as thin lines
(:func:`fit_from_starts`'s ``thin_first``).
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any, Callable

import numpy as np

from springbalance.design.clearance import Clearance, FitRecord, LinearRows
from springbalance.design.clearance_fit import _Checker, _violations, fit_to_arm
from springbalance.design.clearance_round import FALLBACK_STARTS, fall_back
from springbalance.design.clearance_rows import _mount_errors
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution, forked
from springbalance.design.verification import check_design
from springbalance.design.verification_loop import verify_and_resolve
from springbalance.design.worse_joints import weighted_joints_made_worse
from springbalance.model.collision import collision_geometry

#: a fit as a worker returns it: the problem does not pickle, its rows do
Fitted = tuple[Solution, FitRecord, "LinearRows | None"]
#: Designs of the multi-start that lie within this fraction of every variable's range of a better one are that
#: design again, and are not fitted (:func:`distinct_designs`).
SAME_DESIGN = 1e-2
#: the capsule radius [m] of the springs in the first stage of a fit from thin springs (:func:`thin_clearance`)
THIN_RADIUS = 1e-3
#: most fits that :func:`held_at_unseen_poses` repairs (each is a verification with its re-solves)
REPAIRS = 2


def fitted_to_arm(problem: DesignProblem) -> bool:
    """Whether ``problem``'s design is fitted to the arm after its multi-start (:func:`fit_from_starts`): it asks
    for a clearance, or has anchors mounted on the links' surfaces."""
    return problem.clearance is not None or bool(problem.mounts)


def fit_from_starts(
    problem: DesignProblem,
    solution: Solution,
    kept: LinearRows | None = None,
    trusted_first: bool = False,
    tighten: bool = False,
    verify: str = "off",
    thin_first: bool = False,
    **solve_options: Any,
) -> tuple[Solution, FitRecord, DesignProblem]:
    """:func:`~springbalance.design.clearance_fit.fit_to_arm` from the :attr:`Clearance.starts` best distinct
    designs of the multi-start (:func:`distinct_designs`); keeps the converged fit of lowest objective among those
    that carry no weighted joint worse than the bare arm (peak and RMS at the samples: a design the command would
    refuse, ``worse_joint``), else among the converged ones, else the first. When no fit converged, or when every
    converged fit carries a joint worse, the next ranked designs are fitted too, up to
    :data:`~springbalance.design.clearance_round.FALLBACK_STARTS` more; when every accepted fit converged only
    after its rounds moved the design, the next ranked one is fitted too (once). ``trusted_first``:
    each fit's first run has a trust region; ``tighten``: each fitted design is tightened (:func:`fit_to_arm`);
    ``verify``: the solve's verification mode (:data:`~springbalance.design.verification_loop.MODES`); unless
    ``"off"``, of several such fits the best that holds at the verification's unseen poses, in mode ``"resolve"``
    repaired there first (:func:`held_at_unseen_poses`); ``thin_first``: the fits start from a fit of the springs
    as thin lines (:func:`fit_thin_first`). Returns the fit kept with the problem that carries its rows; its record's ``seconds``
    are the wall time of all the fits."""

    def fit(problem: DesignProblem, solution: Solution, verify: str) -> tuple[Solution, FitRecord, DesignProblem]:
        return _fitted_starts(problem, solution, kept, trusted_first, tighten, verify, **solve_options)

    if thin_first and problem.clearance is not None:
        return fit_thin_first(problem, solution, verify, fit)
    return fit(problem, solution, verify)


def _fitted_starts(
    problem: DesignProblem,
    solution: Solution,
    kept: LinearRows | None,
    trusted_first: bool,
    tighten: bool,
    verify: str,
    **solve_options: Any,
) -> tuple[Solution, FitRecord, DesignProblem]:
    """:func:`fit_from_starts` without ``thin_first``."""
    count = problem.clearance.starts if problem.clearance is not None else 1

    def fit(x: np.ndarray) -> Callable[[], Fitted]:
        start = Solution(np.array(x, dtype=float), solution.starts, solution.method, solution.seed, solution.status)

        def task() -> Fitted:
            fitted, record, fitted_problem = fit_to_arm(problem, start, kept, trusted_first, tighten, **solve_options)
            return fitted, record, fitted_problem.linear_rows

        return task

    def accepted(fit: Fitted) -> bool:
        return not weighted_joints_made_worse(problem, fit[0].x)

    def needed(index: int, done: list[Fitted]) -> bool:
        return index < count or fall_back(done, index - count, accepted)

    clock = time.perf_counter()
    tasks = [fit(x) for x in distinct_designs(problem, solution)[: count + FALLBACK_STARTS]]
    done = forked.run_in_order(problem, tasks, needed)
    converged = [fit for fit in done if fit[1].converged]
    ranked = sorted(
        [fit for fit in converged if accepted(fit)] or converged or done[:1], key=lambda fit: fit[1].objective
    )
    if verify == "off":
        fitted, record, rows = ranked[0]
    else:
        fitted, record, rows = held_at_unseen_poses(problem, ranked, verify == "resolve", **solve_options)
    record.starts = len(done)
    if len(done) > 1:
        record.rounds = sum(fit[1].rounds for fit in done)
        record.seconds = time.perf_counter() - clock
    return fitted, record, problem.with_linear_rows(rows)


def fit_thin_first(
    problem: DesignProblem,
    solution: Solution,
    verify: str,
    fit: Callable[[DesignProblem, Solution, str], tuple[Solution, FitRecord, DesignProblem]],
) -> tuple[Solution, FitRecord, DesignProblem]:
    """The fit in two stages, a continuation in the springs' thickness: ``fit`` (:func:`fit_from_starts`'s own,
    ``verify`` in the second stage) of the springs as thin lines (:func:`thin_clearance`), then from its design
    with the clearance as asked (the multi-start's other designs behind it). The record counts the rounds and time of
    both; its objective before is the multi-start's.

    A round's rows are the tangent planes of the distances where the round starts; at a design whose springs lie deep
    in a link they exclude the designs nearby, and a third of the rounds of bench_real's ur5-mounted-clear then had
    no design meeting them (the solver's least violating point, up to 10× the objective, came next). Thin lines
    reach shallow contacts only, and from their fit the capsules grow by their radius and margin, a short step. On
    ur5-mounted-clear the five seeds' lift and elbow cuts came within 0.84 / 0.72 points (1.12 / 4.68 without), each
    objective as low or lower (docs/developer/performance.md, session 49)."""
    assert problem.clearance is not None  # (the caller's condition)
    thin = problem.with_springs(problem.springs, clearance=thin_clearance(problem.clearance))
    first, first_fit, _ = fit(thin, solution, "off")
    start = Solution(np.array(first.x, dtype=float), solution.starts, solution.method, solution.seed, solution.status)
    fitted, record, fitted_problem = fit(problem, start, verify)
    record = dataclasses.replace(
        record,
        rounds=first_fit.rounds + record.rounds,
        seconds=first_fit.seconds + record.seconds,
        objective_before=first_fit.objective_before,
    )
    return fitted, record, fitted_problem


def thin_clearance(clearance: Clearance) -> Clearance:
    """``clearance`` with the capsule of every spring without a coil of its own :data:`THIN_RADIUS` in radius (a
    coil's is half its outer diameter) and no margin: the first stage of :func:`fit_thin_first`."""
    return dataclasses.replace(clearance, radius=THIN_RADIUS, margin=0.0, buffer=None)


def distinct_designs(problem: DesignProblem, solution: Solution) -> list[np.ndarray]:
    """The designs a fit may start from: ``solution.x``, then the multi-start's other feasible designs
    (``solution.starts``), best first, each kept only when some variable lies more than :data:`SAME_DESIGN` of its
    range (1 where the range is not finite) from every design kept before it. Starts that converged to one optimum
    end a few 10⁻³ of a range apart, and their fits, chaotic, part on such differences: on the UR5 with three coils
    on its links' surfaces three of four starts ended at one design (3.5801 N·m), and the fit of each copy was a
    second try of the same design in place of the next one (6.77 N·m)."""
    lower, upper = (np.asarray(bound, dtype=float) for bound in problem.variables.bounds())
    span = upper - lower
    span = np.where(np.isfinite(span) & (span > 0), span, 1.0)
    kept = [np.asarray(solution.x, dtype=float)]
    for record in sorted((record for record in solution.starts if record.feasible), key=lambda r: r.objective):
        x = np.asarray(record.x, dtype=float)
        if all(np.max(np.abs(x - other) / span) > SAME_DESIGN for other in kept):
            kept.append(x)
    return kept


def held_at_unseen_poses(
    problem: DesignProblem, ranked: list[Fitted], repair: bool = False, **solve_options: Any
) -> Fitted:
    """Of the ``ranked`` fits, the best once checked where the verification looks first
    (:func:`~springbalance.design.verification.check_design`, round 0: every rule, the clearance and the residual),
    else the first. A fit is clear at the fit's check poses only, and the lowest of several is the likeliest to have
    found a gap between them. The fits are taken in rank order up to the first that holds as it stands. With
    ``repair``, each one before it that does not hold (the first :data:`REPAIRS` of them) is repaired as the
    verification would repair it (:func:`~springbalance.design.verification_loop.verify_and_resolve`,
    ``solve_options`` its solves'), and the lowest objective of those that then hold is kept: a repaired design with
    that objective in its record and the cuts added to its rows.

    On bench_real's ur5-mounted-clear with 8 fits (seed 4) the best (0.5607 N·m) broke its clearance at unseen
    poses, and the verification's re-solves moved it to 1.577 N·m; the next (0.6666) held, and is kept. On
    ur5-coils-clear at seed 2 the best (1.330) did not hold either, but repaired it held at 1.064, below the next
    (1.845, which held as it stood)."""
    if len(ranked) < 2:
        return ranked[0]
    held: list[tuple[float, Fitted]] = []
    repairs = REPAIRS if repair else 0
    for fit in ranked:
        checked = problem.with_linear_rows(fit[2])
        if repairs > 0:  # the verification's own first check is round 0's: it returns at once when the fit holds
            repairs -= 1
            solution, verification, repaired = verify_and_resolve(checked, fit[0], "resolve", **solve_options)
            if verification.passed and verification.rounds == 0:
                held.append((problem.objective_at(fit[0].x), fit))
                break
            if verification.passed:
                record = repaired_record(fit[1], repaired, solution.x, verification.rounds)
                held.append((record.objective, (solution, record, repaired.linear_rows)))
            continue
        checker = _Checker(checked, checked.clearance) if checked.clearance is not None else None
        if check_design(checked, fit[0].x, 0, checker, "report").record.passed:
            held.append((problem.objective_at(fit[0].x), fit))
            break
    return min(held, key=lambda item: item[0])[1] if held else ranked[0]


def repaired_record(record: FitRecord, repaired: DesignProblem, x: np.ndarray, rounds: int) -> FitRecord:
    """The fit's ``record`` for its design repaired at unseen poses, ``x`` of the problem ``repaired`` (the fit's with
    the cuts the repair added): its objective, the repair's ``rounds`` (re-solves) added to the fit's, the rows the
    design ends with, and each spring's closest distance [m] and each mounted anchor's distance from its surface
    measured at ``x`` as the fit measures them (at its check poses, then denser, then between them)."""
    closest, mounts = dict(record.closest), dict(record.mounts)
    if repaired.clearance is not None:
        closest = _violations(_Checker(repaired, repaired.clearance), x)[1]
    if repaired.mounts:
        mounts = _mount_errors(repaired, x, collision_geometry(repaired.mechanism))
    return dataclasses.replace(
        record,
        rounds=record.rounds + rounds,
        rows=len(repaired.linear_rows) if repaired.linear_rows is not None else 0,
        objective=repaired.objective_at(x),
        closest={name: float(value) for name, value in closest.items()},
        mounts={name: float(value) for name, value in mounts.items()},
    )
