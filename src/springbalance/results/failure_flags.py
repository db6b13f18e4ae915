"""The failures of a design that :mod:`springbalance.results.flags` checks here: it breaks its constraints
(``infeasible``), its solve or its fit to the arm did not finish (``not_converged``), a spring overlaps
the arm (``overlap``), or it was saved unfinished (``partial``).

- ``infeasible``: the evaluation's largest constraint violation (docs/model.md §3) exceeds
  :data:`~springbalance.design.solvers.FEASIBILITY_TOLERANCE` (1e-6 in the row's unit, m or N), or a
  linear row (clearance and mounting, :class:`~springbalance.design.clearance.LinearRows`) is violated
  by more than that while the fit to the arm did not converge. When the fit converged, its own check
  (the true distances at every pose checked, the mounted anchors within 0.5 mm of their surfaces) has
  passed, and a linear row, only a sufficient linearisation of it, is not a violation.
- ``not_converged``: the fit to the arm ended without a clear check (its record's ``converged`` is
  false: a spring still below the margin, or a mounted anchor off its surface, after the last round),
  or (else) the last solver run behind the design ended in an error status: IPOPT's
  :data:`FAILED_STATUSES` or least squares' ``improper input``. A fitting round that stopped
  infeasible (its linearised rows not all met) is judged by the fit's record, not by its status: when
  the fit converged, its check of the true distances and mountings passed. An iteration limit is not a failure:
  the chosen start is feasible and was polished (``polish_iterations``); a lexicographic second phase
  that was not kept (``(not kept)``) leaves the first phase's design, which is not a failure either.
- ``overlap``: the clearance check of the finished design (:func:`~springbalance.results.clearance.checked_clearance`,
  over the workspace's poses, when the URDF has collision geometry) finds a spring's capsule touching
  or inside a link (distance ≤ 0), or, when the design asked for a clearance, closer than its margin.
- ``partial``: the design was saved with ``--partial`` (interrupted, or failing a check).
"""

from __future__ import annotations

import re

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.plateau import PLATEAU_STATUS
from springbalance.design.solvers import FEASIBILITY_TOLERANCE
from springbalance.results.clearance import checked_clearance
from springbalance.results.flag import FAILURE, Flag
from springbalance.results.rules import rule_margins

#: IPOPT's return statuses that mean it failed (every other one, including the iteration limit, is not)
FAILED_STATUSES = (
    "Infeasible_Problem_Detected",
    "Diverging_Iterates",
    "User_Requested_Stop",
    "Restoration_Failed",
    "Error_In_Step_Computation",
    "Maximum_CpuTime_Exceeded",
    "Maximum_WallTime_Exceeded",
    "Not_Enough_Degrees_Of_Freedom",
    "Invalid_Problem_Definition",
    "Invalid_Option",
    "Invalid_Number_Detected",
    "Unrecoverable_Exception",
    "NonIpopt_Exception_Thrown",
    "Insufficient_Memory",
    "Internal_Error",
)
#: IPOPT's return statuses that do not mean a failure
FINISHED_STATUSES = (
    "Solve_Succeeded",
    "Solved_To_Acceptable_Level",
    "Feasible_Point_Found",
    "Search_Direction_Becomes_Too_Small",
    "Maximum_Iterations_Exceeded",
    PLATEAU_STATUS,
)
#: a solver status in a status text: IPOPT's (not followed by " (not kept)"), or least squares' own
_STATUS = re.compile(
    r"(" + "|".join(FAILED_STATUSES + FINISHED_STATUSES) + r")(?! \(not kept\))|least_squares: ([a-z ]+)"
)
#: the note of a fitting round whose linearised rows could not all be met: the fit's own record judges it
_FIT_ROUND = re.compile(r"a fitting round (?:stopped infeasible|ended outside its linearised rows) \([^)]*\)")
#: violated rules named in the ``infeasible`` message
RULES_SHOWN = 3


def last_solver_status(status: str) -> tuple[str, bool] | None:
    """``(status, failed)`` of the last solver run a design's status text names (the design's own: the
    steps after the multi-start append theirs), or None when it names none (a design evaluated, loaded).
    A fitting round that stopped infeasible is not read: the fit's record says whether the fit converged
    (its check of the true distances), which is what counts."""
    found = list(_STATUS.finditer(_FIT_ROUND.sub("", status)))
    if not found:
        return None
    last = found[-1]
    if last.group(1):
        return last.group(1), last.group(1) in FAILED_STATUSES
    return f"least_squares: {last.group(2).strip()}", last.group(2).startswith("improper input")


def infeasible_flags(result: EvaluatedDesign) -> list[Flag]:
    """``infeasible``: constraint rows, or linear rows of an unconverged fit, violated (see the module)."""
    problem = result.problem
    violation = result.evaluation.max_violation
    linear = problem.linear_violation(result.x)
    fitted = result.fit is not None and result.fit.converged
    rows_broken = violation > FEASIBILITY_TOLERANCE
    linear_broken = linear > FEASIBILITY_TOLERANCE and not fitted
    if not (rows_broken or linear_broken):
        return []
    violated = [
        margin
        for margin in rule_margins(result)
        if margin.value < -FEASIBILITY_TOLERANCE and (linear_broken or not margin.linear)
    ]
    shown = ", ".join(f"{m.rule} ({m.value:.3g}{_unit(m.unit)})" for m in violated[:RULES_SHOWN])
    more = len(violated) - RULES_SHOWN
    worst = max(violation if rows_broken else 0.0, linear if linear_broken else 0.0)
    message = (
        f"the design breaks its constraints: largest violation {worst:.3g} (tolerance {FEASIBILITY_TOLERANCE:g})"
        + (f"; violated: {shown}" if shown else "")
        + (f" and {more} more" if more > 0 else "")
    )
    hint = (
        "no start met every rule: try more starts (--starts), wider bounds on the anchors and coils, or "
        "looser rules (envelope, margin); --partial saves it anyway"
    )
    return [Flag("infeasible", "design", message, hint, FAILURE)]


def _unit(unit: str) -> str:
    return "" if unit in ("", "1") else f" {unit}"


def not_converged_flags(result: EvaluatedDesign) -> list[Flag]:
    """``not_converged``: an unconverged fit to the arm, or a failed last solver run (see the module)."""
    found = []
    fit = result.fit
    if fit is not None and not fit.converged:
        closest = ", ".join(f"{name} {1e3 * value:.1f} mm" for name, value in fit.closest.items())
        mounts = ", ".join(f"{name} {1e3 * value:.2f} mm off" for name, value in fit.mounts.items() if value > 5e-4)
        margin = result.problem.clearance.margin if result.problem.clearance is not None else None
        details = "; ".join(
            part
            for part in (
                f"closest approach {closest}" + (f" (margin {1e3 * margin:.1f} mm)" if margin is not None else "")
                if closest
                else "",
                f"mounted anchors {mounts}" if mounts else "",
            )
            if part
        )
        found.append(
            Flag(
                "not_converged",
                "fit",
                f"fitting the springs to the arm did not converge in {fit.rounds_text}"
                + (f": {details}" if details else ""),
                "raise clearance.rounds or clearance.starts, widen the anchor boxes, or lower the margin",
                FAILURE,
            )
        )
    last = last_solver_status(result.status)
    if last is not None and last[1] and not found:  # (an unconverged fit's last round says it already)
        found.append(
            Flag(
                "not_converged",
                "solver",
                f"the last solver run behind this design failed ({last[0]}); status: {result.status}",
                "try more starts (--starts), more iterations (solve.max_iterations) or another --method",
                FAILURE,
            )
        )
    return found


def overlap_flags(result: EvaluatedDesign) -> list[Flag]:
    """``overlap``: springs that touch or enter a link over the workspace, or, when the design asked for a
    clearance, come closer than its margin (see the module)."""
    report = checked_clearance(result)
    if report is None:
        return []
    asked = result.problem.clearance is not None
    found = []
    for row in report.rows:
        if not row.below_margin:
            continue
        where = report.cells(row)[-1]  # the pose as the clearance table shows it (degrees, or m)
        if row.distance <= 0:
            what = f"overlaps link {row.link} by {-1e3 * row.distance:.1f} mm"
        else:
            what = f"comes within {1e3 * row.distance:.1f} mm of link {row.link}, below the margin of {1e3 * report.margin:.1f} mm"
        hint = (
            "raise clearance.rounds or check_samples, or widen the anchor boxes so that the fit can move it"
            if asked
            else "ask for a clearance (clearance: {margin: 0.005}) so that the solver keeps it clear, or move its anchors"
        )
        found.append(
            Flag(
                "overlap",
                row.spring,
                f"spring {row.spring!r} (capsule radius {1e3 * row.radius:.1f} mm) {what} at {where}"
                f" (of {report.poses} workspace poses checked)",
                hint,
                FAILURE,
            )
        )
    return found


def partial_flags(result: EvaluatedDesign) -> list[Flag]:
    """``partial``: the design was saved unfinished with ``--partial``; the message says why."""
    if not result.partial:
        return []
    return [
        Flag(
            "partial",
            "design",
            f"this design was saved with --partial and is not a finished design: {result.partial}",
            "a partial design is kept to be looked at, not built: fix the failures listed (or let the solve "
            "finish) and design again",
            FAILURE,
        )
    ]
