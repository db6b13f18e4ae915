"""Which designs of the multi-start the clearance loop fits, and which fit it keeps
(:mod:`springbalance.design.clearance_starts`, :func:`springbalance.design.clearance_round.fall_back`).

The arm and springs are those of tests/design/test_clearance_constraint.py (two-link planar arm with collision
boxes, a ground→link1 and a link1→link2 zero-free-length spring). The fits are scripted where what is tested is
the choice among them, not the fit itself.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import springbalance as sb
from clearance_helpers import crossing_case
from springbalance.design import clearance_fit, clearance_round, clearance_starts
from springbalance.design.clearance import FitRecord
from springbalance.design.clearance_fit import _Checker
from springbalance.design.solvers import Solution
from springbalance.design.solvers.records import StartRecord
from springbalance.design.verification import check_design
from springbalance.design.worse_joints import weighted_joints_made_worse

OPTIONS = {"method": "auto", "max_iterations": 100, "tolerance": 1e-8, "polish_iterations": None}


@pytest.fixture(scope="module")
def problem():
    return crossing_case(0.005)


def _record(index: int, x: np.ndarray, objective: float, feasible: bool = True) -> StartRecord:
    return StartRecord(index, x, x, objective, 0.0 if feasible else 1.0, "ipopt: Solve_Succeeded", 9, 0.0)


def _stiffness_free(problem: sb.DesignProblem, x: np.ndarray) -> np.ndarray:
    """``x`` with every spring's stiffness 0: the springs carry nothing, so every joint carries what the bare
    arm carries (no joint worse)."""
    out = np.array(x, dtype=float)
    for index, name in enumerate(problem.variables.names):
        if name.endswith(".stiffness"):
            out[index] = 0.0
    return out


def test_copies_of_a_design_are_fitted_once(problem):
    """Starts that ended at one design (within SAME_DESIGN of every variable's range) are one design to fit; a
    design further away on one variable, and an infeasible start, are told apart (the second is not fitted)."""
    fitted, start = problem
    lower, upper = (np.asarray(bound, dtype=float) for bound in fitted.variables.bounds())
    column = int(np.flatnonzero(np.isfinite(upper - lower) & (upper > lower))[0])
    span = upper[column] - lower[column]
    copy, other, broken = (np.array(start) for _ in range(3))
    copy[column] += 0.2 * clearance_starts.SAME_DESIGN * span
    other[column] += 5 * clearance_starts.SAME_DESIGN * span
    records = [_record(0, start, 1.0), _record(1, copy, 1.0), _record(2, other, 1.5), _record(3, broken, 0.5, False)]
    designs = clearance_starts.distinct_designs(fitted, Solution(start, records, "auto", 0, "given"))
    assert len(designs) == 2
    np.testing.assert_array_equal(designs[0], start)
    np.testing.assert_array_equal(designs[1], other)


def test_a_fit_that_makes_a_joint_worse_sends_the_loop_to_the_next_design():
    """While every converged fit carries a weighted joint worse than the bare arm (not accepted), the next ranked
    design is fitted, up to FALLBACK_STARTS more; once one is accepted, the rule of a moved design applies."""
    refused = (Solution(np.zeros(1), [], "ipopt", 0, "ok"), FitRecord(0, 4, True, 1.0, 1.0), None)
    moved = (Solution(np.ones(1), [], "ipopt", 0, "ok"), FitRecord(3, 4, True, 1.0, 2.0), None)

    def accepted(fit) -> bool:
        return fit is not refused

    assert clearance_round.fall_back([refused], 0, accepted)
    assert not clearance_round.fall_back([refused], clearance_round.FALLBACK_STARTS, accepted)
    assert not clearance_round.fall_back([refused], 0)  # without the rule: converged, clear as it stood
    assert clearance_round.fall_back([refused, moved], 1, accepted) is False  # moved is accepted: compared once
    assert clearance_round.fall_back([moved], 0, accepted)


def test_no_further_design_is_fitted_once_a_moved_fit_ends_at_the_best_objective():
    """A fit adds rows to the problem, so a fit that ends within AT_BEST of the best design's objective before any
    fit is as good as another could end: the next ranked design is not fitted, though the rounds moved the design."""

    def fit(objective: float):
        return (Solution(np.ones(1), [], "ipopt", 0, "ok"), FitRecord(10, 4, True, 1.0, objective), None)

    assert not clearance_round.fall_back([fit(0.95)], 0)  # below it (the multi-start's own polish was looser)
    assert not clearance_round.fall_back([fit(1.0 + 0.5 * clearance_round.AT_BEST)], 0)
    assert clearance_round.fall_back([fit(1.0 + 2.0 * clearance_round.AT_BEST)], 0)


def test_the_fit_kept_carries_no_weighted_joint_worse_when_one_does_not(problem, monkeypatch):
    """Two designs fitted (scripted): the better one by objective carries the elbow's peak above the bare arm's
    (the in-plane optimum of this arm does: 4.63 against 3.92 N·m), the other has no spring force and carries
    what the bare arm carries. The fit kept is the second; its problem is the one with its rows."""
    fitted, start = problem
    assert weighted_joints_made_worse(fitted, start) == ["elbow"]  # the premise
    idle = _stiffness_free(fitted, start)
    assert weighted_joints_made_worse(fitted, idle) == []
    calls: list[np.ndarray] = []

    def scripted(problem, solution, kept=None, trusted_first=False, tighten=False, **options):
        calls.append(np.array(solution.x))
        x = np.array(solution.x)
        record = FitRecord(0, 0, True, 0.0, float(problem.objective_value(problem.evaluate(x))))
        return solution, record, problem

    monkeypatch.setattr(clearance_starts, "fit_to_arm", scripted)
    records = [_record(0, start, 1.0), _record(1, idle, 2.0)]
    solution, fit, rows = clearance_starts.fit_from_starts(
        fitted, Solution(start, records, "auto", 0, "given"), **OPTIONS
    )
    assert len(calls) == 2 and fit.starts == 2
    np.testing.assert_array_equal(solution.x, idle)
    assert fit.objective > float(fitted.objective_value(fitted.evaluate(start)))  # kept although higher
    assert rows is not None


@pytest.fixture(scope="module")
def clear_only_at_the_fits_poses(problem):
    """Two fits of the crossing case: the in-plane optimum, which the fit's 64 check poses find clear but the
    verification's unseen poses do not (s1 reaches into link2 between them), and the design the fit moves it to,
    which holds there."""
    fitted, start = problem
    solution, record, rows_problem = clearance_fit.fit_to_arm(
        fitted, Solution(start, [], "auto", 0, "given"), **OPTIONS
    )
    checker = _Checker(fitted, fitted.clearance)
    assert not check_design(fitted, start, 0, checker, "report").record.passed  # the premise
    assert check_design(rows_problem, solution.x, 0, _Checker(rows_problem, fitted.clearance), "report").record.passed
    unseen = (Solution(start, [], "auto", 0, "given"), FitRecord(0, 0, True, 1.0, 1.0), None)
    held = (solution, FitRecord(record.rounds, 0, True, 1.0, 2.0), rows_problem.linear_rows)
    return unseen, held


def test_of_several_fits_the_best_that_holds_at_unseen_poses_is_kept(problem, clear_only_at_the_fits_poses):
    fitted, _ = problem
    unseen, held = clear_only_at_the_fits_poses
    assert clearance_starts.held_at_unseen_poses(fitted, [unseen, held]) is held
    assert clearance_starts.held_at_unseen_poses(fitted, [held, unseen]) is held
    # one fit: nothing to choose, no check; none holds: the best, which the verification then re-solves
    assert clearance_starts.held_at_unseen_poses(fitted, [unseen]) is unseen
    other = (unseen[0], FitRecord(0, 0, True, 1.0, 1.5), None)
    assert clearance_starts.held_at_unseen_poses(fitted, [unseen, other]) is unseen


def test_with_repair_a_better_fit_repaired_at_unseen_poses_beats_a_worse_one_that_held(
    problem, clear_only_at_the_fits_poses, monkeypatch
):
    """The fit that does not hold is repaired as the verification would (re-solved with the poses and cuts where it
    fails); repaired it holds, and is kept when its objective is the lower, with that objective in its record and the
    cuts in its rows. The next fit here holds as it stands but carries nothing (the held fit's anchors, every
    stiffness 0: the bare arm's objective). When the repair does not hold, that next fit is kept."""
    fitted, _ = problem
    unseen, held = clear_only_at_the_fits_poses
    idle_x = _stiffness_free(fitted, held[0].x)
    idle = (Solution(idle_x, [], "auto", 0, "given"), FitRecord(0, 0, True, 1.0, 3.0), held[2])
    bare = float(fitted.objective_value(fitted.evaluate(idle_x)))
    solution, record, rows = clearance_starts.held_at_unseen_poses(fitted, [unseen, idle], repair=True, **OPTIONS)
    repaired = fitted.with_linear_rows(rows)
    assert check_design(repaired, solution.x, 0, _Checker(repaired, fitted.clearance), "report").record.passed
    kept = float(fitted.objective_value(fitted.evaluate(solution.x)))
    assert record.objective == pytest.approx(kept, rel=1e-12) and kept < 0.5 * bare
    assert not np.allclose(solution.x, unseen[0].x)  # moved off the design that failed
    assert len(rows) > len(unseen[2] or ())  # with the cuts where it failed
    # the record describes the repaired design: its re-solves, its rows, its distances at the fit's poses (clear)
    assert record.rounds > unseen[1].rounds and record.rows == len(rows)
    assert set(record.closest) == {spring.name for spring in fitted.springs}  # (the scripted fit's record has none)
    assert min(record.closest.values()) >= fitted.clearance.margin - 1e-9

    def unrepaired(problem, solution, mode, fixed=(), **options):
        record = check_design(problem, solution.x, 0, _Checker(problem, problem.clearance), "report").record
        return solution, record, problem

    monkeypatch.setattr(clearance_starts, "verify_and_resolve", unrepaired)
    assert clearance_starts.held_at_unseen_poses(fitted, [unseen, idle], repair=True, **OPTIONS) is idle


@pytest.mark.parametrize("verify", ["report", "off"])
def test_fit_from_starts_ranks_its_fits_at_unseen_poses_when_the_design_is_verified(
    problem, clear_only_at_the_fits_poses, monkeypatch, verify
):
    """Two designs fitted (``Clearance.starts`` 2), scripted as the fits of :func:`clear_only_at_the_fits_poses`,
    neither making a joint worse: the lower is kept unless the design is to be verified (the solve's ``verify`` is
    not "off"), when the one that holds at unseen poses is."""
    fitted, start = problem
    fitted = fitted.with_springs(fitted.springs, clearance=dataclasses.replace(fitted.clearance, starts=2))
    unseen, held = clear_only_at_the_fits_poses

    def scripted(problem, solution, kept=None, trusted_first=False, tighten=False, **options):
        fit = unseen if np.array_equal(solution.x, start) else held
        return fit[0], fit[1], problem.with_linear_rows(fit[2])

    monkeypatch.setattr(clearance_starts, "fit_to_arm", scripted)
    monkeypatch.setattr(clearance_starts, "weighted_joints_made_worse", lambda problem, x: [])
    records = [_record(0, start, 1.0), _record(1, np.array(held[0].x), 2.0)]
    solution, fit, _ = clearance_starts.fit_from_starts(
        fitted, Solution(start, records, "auto", 0, "given"), verify=verify, **OPTIONS
    )
    assert fit.starts == 2
    np.testing.assert_array_equal(solution.x, (held if verify == "report" else unseen)[0].x)


def test_the_thin_stage_is_the_clearance_with_thin_lines_and_no_margin(problem):
    fitted, _ = problem
    thin = clearance_starts.thin_clearance(fitted.clearance)
    assert thin.radius == clearance_starts.THIN_RADIUS and thin.margin == 0.0
    assert thin.check_samples == fitted.clearance.check_samples and thin.rounds == fitted.clearance.rounds
    assert fitted.clearance.margin == 0.005  # the problem's own is left as it was


def test_a_fit_from_thin_springs_first_ends_clear_and_counts_both_stages(problem, monkeypatch):
    """The crossing case fitted in two stages (real fits): thin lines first, then the capsules and margin asked; the
    design kept holds at the verification's unseen poses, and the record counts both stages' rounds."""
    fitted, start = problem
    stages: list[tuple[float, int]] = []
    ends: list[tuple[np.ndarray, np.ndarray]] = []  # (start, fitted design) of each fit
    real = clearance_starts.fit_to_arm

    def recorded(problem, solution, *args, **kwargs):
        out = real(problem, solution, *args, **kwargs)
        stages.append((problem.clearance.margin, out[1].rounds))
        ends.append((np.array(solution.x), np.array(out[0].x)))
        return out

    monkeypatch.setattr(clearance_starts, "fit_to_arm", recorded)
    records = [_record(0, start, float(fitted.objective_value(fitted.evaluate(start))))]
    solution, fit, rows_problem = clearance_starts.fit_from_starts(
        fitted, Solution(start, records, "auto", 0, "given"), thin_first=True, **OPTIONS
    )
    # thin first (one design), then as asked (from there, and the next design when the fit moved it)
    assert stages[0][0] == 0.0 and len(stages) >= 2 and all(margin == 0.005 for margin, _ in stages[1:])
    np.testing.assert_array_equal(ends[1][0], ends[0][1])  # the fit as asked starts where the thin one ended
    assert fit.converged and fit.rounds == sum(rounds for _, rounds in stages)
    assert fit.objective_before == pytest.approx(float(fitted.objective_value(fitted.evaluate(start))))
    checker = _Checker(rows_problem, fitted.clearance)
    assert check_design(rows_problem, solution.x, 0, checker, "report").record.passed
