"""Warnings of a design (springbalance.results.flags): each kind provoked by a small real problem
and found in the text report, in report.html and in the saved design.json.

Physics of the single link (urdf/single_link_r1.urdf, docs/model.md §9): link of m = 8 kg with its
centre of mass c = 0.183 m from the pivot, joint angle phi from the upward vertical, workspace
phi ∈ [120°, 180°] (the URDF limits). A spring from a = 0.16 m above the pivot to b along the link
has length ``L² = a² + b² − 2 a b cos(phi)`` and ``dL/dphi = a b sin(phi) / L``; gravity needs
``−m g c sin(phi)`` and a zero-free-length spring k adds ``k a b sin(phi)``, so it balances exactly
at ``k* = m g c / (a b)`` = 299.2 N/m for b = 0.3 m.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from flag_helpers import assert_clean, assert_flagged, slider_pull
from springbalance.cli import main

URDF = Path(__file__).resolve().parents[2] / "urdf"
M, C, G = 8.0, 0.183, 9.81  # link mass [kg], centre of mass [m], gravity [m/s²]
A, B = 0.16, 0.3  # ground anchor height, link anchor distance [m]
K_STAR = M * G * C / (A * B)  # exact balance [N/m]


@pytest.fixture(scope="module")
def link():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    return mechanism, sb.Workspace.grid(mechanism, 31)


def _anchors(b: float = B):
    return sb.Anchor("universe", (0, 0, A)), sb.Anchor("link1", (0, 0, b))


def _lengths(workspace, b: float = B) -> np.ndarray:
    phi = workspace.joint_values[:, 0]
    return np.sqrt(A**2 + b**2 - 2 * A * b * np.cos(phi))


def _of_kind(result, kind: str) -> list:
    return [flag for flag in result.warnings() if flag.kind == kind]


# ---------------------------------------------------------------------- at_bound
def test_stiffness_capped_below_balance_is_at_its_upper_bound(link, tmp_path):
    mechanism, workspace = link
    # residual (k a b − m g c) sin(phi) shrinks as k grows towards k* = 299 N/m, so with k ≤ 100 N/m
    # the best rate is the cap itself
    spring = sb.ZeroFreeLengthSpring(*_anchors(), name="s1", stiffness=sb.Free(0, 100))
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=2)
    assert result.variables["s1.stiffness"] == pytest.approx(100, rel=1e-6)
    record = assert_flagged(result, tmp_path, "at_bound", "s1.stiffness")
    assert "upper bound 100 N/m" in record["message"]
    assert record["hint"] == "raise s1.stiffness's upper bound (100 N/m)"
    # the balance improved, so no joint is worse; a zero-free-length spring has no law or sizing warning
    assert [flag.kind for flag in result.warnings()] == ["at_bound"]

    # the CLI prints the same section
    assert main(["evaluate", str(tmp_path / "design.json")]) == 0


def test_evaluate_prints_the_warnings(link, tmp_path, capsys):
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(*_anchors(), name="s1", stiffness=sb.Free(0, 100))
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), [100.0])
    path = result.save(tmp_path / "design.json")
    assert main(["evaluate", str(path)]) == 0
    out = capsys.readouterr().out
    assert "Warnings (1)" in out
    assert "[at_bound] s1.stiffness" in out and "raise s1.stiffness's upper bound (100 N/m)" in out


def test_stiffness_floor_above_balance_is_at_its_lower_bound(link):
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(*_anchors(), name="s1", stiffness=sb.Free(400, 1000))
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=1)
    assert result.variables["s1.stiffness"] == pytest.approx(400, rel=1e-6)
    (flag,) = _of_kind(result, "at_bound")
    assert flag.subject == "s1.stiffness" and "lower bound 400 N/m" in flag.message
    assert flag.hint == "lower s1.stiffness's lower bound (400 N/m)"


def test_balanced_link_has_no_warnings(link, tmp_path):
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(*_anchors(), name="s1", stiffness=sb.Free(0, 1000))
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=2)
    assert result.variables["s1.stiffness"] == pytest.approx(K_STAR, rel=1e-6)  # inside its bounds
    assert_clean(result, tmp_path)


def test_fixed_coordinates_of_a_box_are_not_variables(link):
    # a box anchor free only along z: x and y (equal bounds) are no variables and are never flagged,
    # z stops strictly inside [0.2, 0.4] at b = m g c / (k a) = 0.3 m for k = k*
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, A)),
        sb.Anchor("link1", sb.Free([0, 0, 0.2], [0, 0, 0.4])),
        name="s1",
        stiffness=K_STAR,
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=2)
    assert result.problem.variables.names == ["s1.b.z"]
    assert result.variables["s1.b.z"] == pytest.approx(B, rel=1e-6)
    assert _of_kind(result, "at_bound") == []


# ---------------------------------------------------------------------- worse_joint
def test_too_stiff_spring_makes_the_joint_worse(link, tmp_path):
    mechanism, workspace = link
    # k = 3 k*: residual (3 − 1) m g c sin(phi), twice the unbalanced torque at every pose
    spring = sb.ZeroFreeLengthSpring(*_anchors(), name="s1", stiffness=3 * K_STAR)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    (row,) = result.metrics()["joints"]
    assert row["peak_after"] == pytest.approx(2 * row["peak_before"], rel=1e-9)
    assert row["rms_after"] == pytest.approx(2 * row["rms_before"], rel=1e-9)
    # the pivot has weight 1: the design was asked to balance it, so a worse pivot is a failure
    record = assert_flagged(result, tmp_path, "worse_joint", "pivot", severity="failure")
    assert "peak" in record["message"] and "RMS" in record["message"]
    # the hint names the setting that holds the joint within what the bare arm carries
    assert "no_joint_worse: true" in record["hint"]


def test_joint_gravity_does_not_load_is_worse_when_a_spring_loads_it(tmp_path):
    # A horizontal slide carries a pendulum: gravity (along −z) never loads the slide (axis x).
    # A zero-free-length spring from the origin to the cart pulls it back with k·q [N], so the
    # slide goes from 0 to k q_max = 100 N/m × 0.3 m = 30 N; the pendulum's joint is untouched.
    result = slider_pull(tmp_path)
    rows = {row["joint"]: row for row in result.metrics()["joints"]}
    assert rows["slide"]["peak_before"] == pytest.approx(0, abs=1e-12)
    assert rows["slide"]["peak_after"] == pytest.approx(100 * 0.3, rel=1e-9)
    assert rows["pitch"]["peak_after"] == pytest.approx(rows["pitch"]["peak_before"], rel=1e-12)
    record = assert_flagged(result, tmp_path, "worse_joint", "slide", severity="failure")
    assert "30 N" in record["message"]
    assert [flag.subject for flag in _of_kind(result, "worse_joint")] == ["slide"]


# ---------------------------------------------------------------------- law
def test_slack_extension_spring_is_a_law_warning(link, tmp_path):
    mechanism, workspace = link
    # l0 = 0.43 m while the spring spans 0.4045 … 0.46 m: slack wherever L < l0 (keep_tension off)
    free_length = 0.43
    lengths = _lengths(workspace)
    slack = int(np.sum(lengths < free_length))
    assert 0 < slack < workspace.size
    spring = sb.ExtensionSpring(*_anchors(), name="loose", stiffness=100.0, free_length=free_length, keep_tension=False)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    record = assert_flagged(result, tmp_path, "law", "loose")
    assert f"{slack} of {workspace.size} workspace samples" in record["message"]
    assert "keep_tension" in record["hint"]


def test_taut_buildable_extension_spring_has_no_warnings(link, tmp_path):
    mechanism, workspace = link
    # l0 = 0.3 m < 0.4045 m: always stretched; k = 100 N/m carries 10.5 … 16 N and only lowers the
    # torque (it pulls against gravity); 16 N on a 300 mm coil is easily wound of music wire
    lengths = _lengths(workspace)
    assert lengths.min() > 0.3
    spring = sb.ExtensionSpring(*_anchors(), name="taut", stiffness=100.0, free_length=0.3, keep_tension=False)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    assert_clean(result, tmp_path)


# ---------------------------------------------------------------------- unbuildable_ideal
def _strongest_music_wire_force() -> float:
    """Largest force [N] any music-wire coil can carry: the thickest wire (6.5 mm) at the smallest
    index C = 4, allowable shear 0.45 S_ut with S_ut = 2211 MPa·mm^0.145 / d^0.145 and the Wahl
    factor (Shigley ch. 10): F = π (0.45 S_ut) d² / (8 K_W C)."""
    d_mm, index = 6.5, 4.0
    strength = 2211e6 / d_mm**0.145  # [Pa]
    wahl = (4 * index - 1) / (4 * index - 4) + 0.615 / index
    return np.pi * 0.45 * strength * (d_mm * 1e-3) ** 2 / (8 * wahl * index)


def test_stiff_short_ideal_spring_is_unbuildable(link, tmp_path):
    mechanism, workspace = link
    # k = 20000 N/m, l0 = 0.02 m stretched to 0.5 m (b = 0.34 m, phi = 180°): 9600 N, more than
    # four times what the strongest music-wire coil carries (about 2.2 kN)
    spring = sb.ExtensionSpring(*_anchors(0.34), name="stiff", stiffness=20000.0, free_length=0.02)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    largest = 20000.0 * (A + 0.34 - 0.02)
    assert largest == pytest.approx(9600)
    assert largest > 4 * _strongest_music_wire_force()
    record = assert_flagged(result, tmp_path, "unbuildable_ideal", "stiff")
    assert "9600 N" in record["message"] and "music_wire" in record["message"]


def test_compression_is_sized_but_gas_springs_are_not(link):
    mechanism, workspace = link
    # pushed from l0 = 0.6 m down to 0.4423 m (b = 0.34 m, phi = 120°): 20000 × 0.158 ≈ 3150 N, beyond
    # any music-wire coil. A gas spring of the same law is no coil and is not sized.
    shortest = float(_lengths(workspace, 0.34).min())
    assert 20000.0 * (0.6 - shortest) > _strongest_music_wire_force()
    springs = [
        sb.CompressionSpring(*_anchors(0.34), name="coil", stiffness=20000.0, free_length=0.6),
        sb.GasSpring(*_anchors(0.34), name="gas", stiffness=20000.0, free_length=0.6),
    ]
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, springs), np.zeros(0))
    assert [flag.subject for flag in _of_kind(result, "unbuildable_ideal")] == ["coil"]


def test_spring_without_rate_is_not_sized(link):
    mechanism, workspace = link
    # k = 0: a constant initial tension, nothing to size (and no division by zero)
    spring = sb.ExtensionSpring(*_anchors(), name="flat", stiffness=0.0, free_length=0.3, initial_tension=20.0)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    assert _of_kind(result, "unbuildable_ideal") == []


# ---------------------------------------------------------------------- not_verified
def test_a_broken_rule_at_unseen_poses_gets_the_hint_of_what_the_verification_tried():
    from springbalance.results.flags import verification_hint

    # reported only: the hint is to let the verification re-solve
    assert "verify='resolve'" in verification_hint("report", 0, "tension")
    # no re-solve met the poses added (the UR5 with coils mounted on its links: a spring 0.25 mm into
    # wrist_3_link where the arm folds onto itself): more samples would not help; the hint names the workspace,
    # the anchor boxes and the fit's check poses, and does not claim re-solves that were never made
    stuck = verification_hint("resolve", 0, "clearance")
    assert "no re-solve" in stuck and "re-solve(s)" not in stuck
    assert all(word in stuck for word in ("workspace", "anchor boxes", "clearance.check_samples"))
    assert "more workspace samples" not in stuck
    # re-solves were made and did not clear a coil's rule: they are counted, and more samples is the advice
    tried = verification_hint("resolve", 3, "body_stress")
    assert tried.startswith("3 re-solve(s)") and tried.endswith("use more workspace samples")
