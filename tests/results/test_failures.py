"""Failures of a design (springbalance.results.failure_flags and the failing kinds of flags.py): each kind
provoked by a small constructed design, found under "Failures" in every report, in result.failures() and
design.json's "failures"; a design that passes has none.

Physics of the single link (urdf/single_link_r1.urdf, as in test_flags.py): m = 8 kg, centre of mass
c = 0.183 m, phi ∈ [120°, 180°]; a spring from a = 0.16 m above the pivot to b = 0.3 m along the link has
length L² = a² + b² − 2ab cos(phi), shortest at phi = 120°: L = √(0.0256 + 0.09 + 0.048) = 0.40447 m;
a zero-free-length spring k* = m g c / (a b) = 299.2 N/m balances it exactly.

The two-link arm with collision shapes (urdf/two_link_planar_collision.urdf, as in test_clearance.py):
link1's box is 0.5 × 0.04 × 0.04 m centred 0.25 m along x; at the pose (0, 0) link1 lies along world x,
its top face at z = 0.02 m, and link2's frame sits at (0.5, 0, 0).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from flag_helpers import assert_clean, assert_flagged, overloaded_coil, slider_pull
from springbalance.design.clearance import FitRecord, LinearRows
from springbalance.results.failure_flags import last_solver_status

URDF = Path(__file__).resolve().parents[2] / "urdf"
M, C, G = 8.0, 0.183, 9.81  # link mass [kg], centre of mass [m], gravity [m/s²]
A, B = 0.16, 0.3  # ground anchor height, link anchor distance [m]
K_STAR = M * G * C / (A * B)  # exact balance [N/m]
SHORTEST = np.sqrt(A**2 + B**2 - 2 * A * B * np.cos(2 * np.pi / 3))  # [m] at phi = 120°


@pytest.fixture(scope="module")
def link():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    return mechanism, sb.Workspace.grid(mechanism, 31)


@pytest.fixture(scope="module")
def arm():
    return sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")


def _anchors():
    return sb.Anchor("universe", (0, 0, A)), sb.Anchor("link1", (0, 0, B))


def _balanced(link, **info) -> sb.DesignResult:
    """The exactly balanced link (k*, zero free length): no finding at all, unless ``info`` adds one."""
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(*_anchors(), name="s1", stiffness=K_STAR)
    return sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0), **info)


def test_the_balanced_link_passes(link, tmp_path):
    result = _balanced(link)
    assert result.failures() == [] and result.ok
    assert_clean(result, tmp_path)


# ---------------------------------------------------------------------- infeasible
def test_a_slack_tension_spring_is_infeasible(link, tmp_path):
    mechanism, workspace = link
    # keep_tension (the default) asks L − l0 ≥ 0 at every sample; l0 = 0.43 m exceeds the shortest length
    # 0.40447 m, so the row is violated by 0.43 − 0.40447 = 0.0255 m
    spring = sb.ExtensionSpring(*_anchors(), name="slack", stiffness=100.0, free_length=0.43)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    assert result.evaluation.max_violation == pytest.approx(0.43 - SHORTEST, rel=1e-9)
    record = assert_flagged(result, tmp_path, "infeasible", "design", severity="failure")
    assert f"largest violation {0.43 - SHORTEST:.3g}" in record["message"]
    assert f"slack: tension ({SHORTEST - 0.43:.3g} m)" in record["message"]
    assert not result.ok
    # the text keeps its INFEASIBLE line, and the failures come before the warnings
    table = result.table()
    assert "INFEASIBLE" in table and table.index("Failures (") < table.index("Warnings")


def test_violated_linear_rows_are_infeasible_unless_the_fit_converged(link):
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, A)), sb.Anchor("link1", sb.Free([0, 0, 0.2], [0, 0, 0.4])), "s1", stiffness=K_STAR
    )
    problem = sb.DesignProblem(mechanism, workspace, [spring])
    # one row s1.b.z − 0.35 ≥ 0 [m], violated by 0.05 m at b.z = 0.3 (the balanced design)
    rows = LinearRows(["s1.b.z"], np.array([[1.0]]), np.array([-0.35]), ["s1 clear of link1_0 (pose 0:3), end b"])
    fitted = problem.with_linear_rows(rows)
    unconverged = FitRecord(2, 1, False, 0.0, 0.0, {"s1": -0.004})
    result = sb.DesignResult(fitted, [0.3], fit=unconverged)
    (flag,) = [flag for flag in result.failures() if flag.kind == "infeasible"]
    assert "largest violation 0.05" in flag.message and "s1 clear of link1_0 (-0.05 m)" in flag.message
    # a converged fit passed its own check of the true distances: its linearised rows are no violation
    converged = FitRecord(2, 1, True, 0.0, 0.0, {"s1": 0.006})
    assert sb.DesignResult(fitted, [0.3], fit=converged).failures() == []


# ---------------------------------------------------------------------- not_converged
def test_an_unconverged_fit_is_a_failure(link, tmp_path):
    fit = FitRecord(12, 40, False, 1.0, 1.5, {"s1": -0.0021}, {}, 4096)
    result = _balanced(link, fit=fit)
    record = assert_flagged(result, tmp_path, "not_converged", "fit", severity="failure")
    assert "did not converge in 12 round(s)" in record["message"] and "s1 -2.1 mm" in record["message"]
    # the record survives the file: the loaded design fails the same way
    loaded = sb.DesignResult.load(tmp_path / "design.json")
    assert [flag.kind for flag in loaded.failures()] == ["not_converged"]


def test_rounds_over_several_fitted_starts_say_so(link, tmp_path):
    # three designs of the multi-start fitted, 7 rounds between them: neither "7 rounds" of one fit
    fit = FitRecord(7, 40, False, 1.0, 1.5, {"s1": -0.0021}, {}, 4096, 3.0, 3)
    result = _balanced(link, fit=fit)
    record = assert_flagged(result, tmp_path, "not_converged", "fit", severity="failure")
    assert "did not converge in 7 round(s) over 3 starts" in record["message"]
    assert "fitted to the arm in 7 round(s) over 3 starts (40 linearised rows" in result.table()


@pytest.mark.parametrize(
    ("status", "failed"),
    [
        ("ipopt: Restoration_Failed", "Restoration_Failed"),
        ("least_squares: improper input", "least_squares: improper input"),
        # the steps after the multi-start append their own solves: the last one counts
        (
            "ipopt: Solve_Succeeded; wire of s1 at standard sizes (ipopt: Error_In_Step_Computation)",
            "Error_In_Step_Computation",
        ),
        ("ipopt: Invalid_Number_Detected; fitted to the arm in 2 round(s)", "Invalid_Number_Detected"),
    ],
)
def test_a_failed_last_solver_run_is_a_failure(link, status, failed):
    (flag,) = _balanced(link, status=status).failures()
    assert flag.kind == "not_converged" and flag.subject == "solver" and f"failed ({failed})" in flag.message


@pytest.mark.parametrize(
    "status",
    [
        "ipopt: Solve_Succeeded",
        # an iteration limit on the chosen (feasible, polished) start is not a failure
        "ipopt: Maximum_Iterations_Exceeded (polished after 100 iterations)",
        "least_squares: iteration limit reached",
        # a later successful run replaces a failed one
        "ipopt: Restoration_Failed; wire of s1 at standard sizes (least_squares: converged (gradient))",
        # a lexicographic second phase that was not kept leaves the first phase's design
        "ipopt: Solve_Succeeded, then Restoration_Failed (not kept)",
        # a fitting round that missed its linearised rows: the fit's record judges it (here: no fit record,
        # so nothing says the fit failed)
        "least_squares: iteration limit reached; a fitting round stopped infeasible (ipopt: Infeasible_Problem_Detected); "
        "fitted to the arm in 11 round(s)",
        "evaluated",
    ],
)
def test_finished_statuses_are_no_failure(link, status):
    assert _balanced(link, status=status).failures() == []


def test_last_solver_status_reads_the_last_run():
    assert last_solver_status("evaluated") is None
    assert last_solver_status("ipopt: Restoration_Failed; x (ipopt: Solve_Succeeded)") == ("Solve_Succeeded", False)
    assert last_solver_status("least_squares: converged (gradient)") == ("least_squares: converged", False)


# ---------------------------------------------------------------------- unbuildable
def test_an_overloaded_coil_is_an_unbuildable_failure(tmp_path):
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 31)
    # 1 mm wire, D = 8 mm, 10 coils: k ≈ 1978 N/m, free length 25 mm, stretched to about 0.43 m: ≈ 800 N
    # on a wire whose body allows about 20 N (tests/springs/test_helical.py)
    coil = overloaded_coil()
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [coil]), np.zeros(0))
    record = assert_flagged(result, tmp_path, "unbuildable", "thin", severity="failure")
    assert "cannot be built" in record["message"]


# ---------------------------------------------------------------------- worse_joint
def test_a_worse_joint_of_weight_zero_is_only_a_warning(tmp_path):
    # the slider of test_flags.py: a spring loads the horizontal slide (0 → 30 N) that gravity never loads;
    # with the slide's weight 0 the design was not asked to balance it
    weighted = slider_pull(tmp_path)
    assert [flag.kind for flag in weighted.failures()] == ["worse_joint"]
    unweighted = slider_pull(tmp_path, weights={"slide": 0.0, "pitch": 1.0})
    assert unweighted.failures() == [] and unweighted.ok
    assert_flagged(unweighted, tmp_path, "worse_joint", "slide", severity="warning")


# ---------------------------------------------------------------------- overlap
def test_a_spring_through_a_link_overlaps_it(arm, tmp_path):
    # from (0.25, 0, −0.1) on the ground to (0.2, 0, 0.1) on link2, at (0.7, 0, 0.1) at the pose (0, 0): the
    # segment crosses z = 0 at x = 0.25 + 0.45 · 0.5 = 0.475 m, inside link1's box (x ∈ [0, 0.5], |z| ≤ 0.02)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0.25, 0, -0.1)), sb.Anchor("link2", (0.2, 0, 0.1)), "through", stiffness=10.0
    )
    problem = sb.DesignProblem(arm, sb.Workspace.from_array(arm, [[0.0, 0.0]]), [spring])
    result = sb.DesignResult(problem, np.zeros(0))
    assert result.clearance().row("through").distance < 0
    record = assert_flagged(result, tmp_path, "overlap", "through", severity="failure")
    assert "overlaps link link1" in record["message"]


def _above_link1(arm, clearance=None) -> sb.DesignResult:
    # from (0.1, 0, 0.033) on the ground to (0.1, 0, 0.033) on link2, at (0.6, 0, 0.033) at the pose (0, 0):
    # parallel to link1's top face (z = 0.02) over x ∈ [0.1, 0.5]; a capsule of radius 0.01 m keeps
    # 0.033 − 0.02 − 0.01 = 3 mm from it (link2 and the ground are its exempt anchor bodies; the tool's
    # sphere is 0.29 m away)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0.1, 0, 0.033)), sb.Anchor("link2", (0.1, 0, 0.033)), "over", stiffness=10.0
    )
    problem = sb.DesignProblem(
        arm,
        sb.Workspace.from_array(arm, [[0.0, 0.0]]),
        [spring],
        clearance=clearance,
    )
    return sb.DesignResult(problem, np.zeros(0))


def test_a_spring_below_the_asked_margin_fails_and_without_a_margin_passes(arm, tmp_path):
    clear = _above_link1(arm)
    assert clear.clearance().row("over").distance == pytest.approx(0.003, abs=1e-9)
    assert [flag.kind for flag in clear.warnings() if flag.kind == "overlap"] == []
    close = _above_link1(arm, sb.Clearance(margin=0.005))
    record = assert_flagged(close, tmp_path, "overlap", "over", severity="failure")
    assert "within 3.0 mm of link link1, below the margin of 5.0 mm" in record["message"]


# ---------------------------------------------------------------------- partial
def test_a_partial_design_says_so_and_keeps_saying_so_after_loading(link, tmp_path):
    result = _balanced(link, partial="interrupted: 2 of 8 starts had finished")
    record = assert_flagged(result, tmp_path, "partial", "design", severity="failure")
    assert "2 of 8 starts had finished" in record["message"]
    saved = json.loads((tmp_path / "design.json").read_text())
    assert saved["partial"] is True and saved["partial_reason"] == "interrupted: 2 of 8 starts had finished"
    loaded = sb.DesignResult.load(tmp_path / "design.json")
    assert loaded.partial == result.partial and [flag.kind for flag in loaded.failures()] == ["partial"]


def test_a_damaged_partial_marker_is_an_input_error(link, tmp_path):
    path = _balanced(link).save(tmp_path / "design.json")
    record = json.loads(path.read_text())
    path.write_text(json.dumps({**record, "partial": "yes"}))
    with pytest.raises(sb.InputError, match="partial: expected true or false"):
        sb.DesignResult.load(path)
