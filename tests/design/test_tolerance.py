"""The worst case over the springs' tolerance box and the adjuster travel (docs/model.md §3.10), against
brute force: all 8² = 64 corner combinations of a two-spring design, each evaluated by the library as a
design of its own (no moment arms, no separability), and the least-squares adjustment solved per corner
with the adjuster's torque column taken by finite differences of the free length.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.tolerance import analyse_tolerance
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.errors import InputError
from tolerance_helpers import LAWS, SPEC, corner_laws, two_springs

URDF = Path(__file__).resolve().parents[2] / "urdf"


@pytest.fixture(scope="module")
def case():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    rng = np.random.default_rng(3)
    workspace = sb.Workspace.from_array(mechanism, rng.uniform(-1.2, 1.2, size=(40, 2)))
    problem = sb.DesignProblem(mechanism, workspace, two_springs(LAWS))
    design = sb.EvaluatedDesign(problem, np.zeros(0))

    def tau(laws):
        return sb.DesignProblem(mechanism, workspace, two_springs(laws)).evaluate(np.zeros(0)).tau

    corners = {corner: (laws, tau(laws)) for corner, laws in corner_laws()}
    return design, tau, corners


def test_envelope_equals_brute_force(case):
    design, _, corners = case
    analysis = analyse_tolerance(design, SPEC)
    stack = np.stack([tau for _, tau in corners.values()])  # 64×N×nv
    np.testing.assert_allclose(analysis.upper, stack.max(axis=0), rtol=0, atol=1e-9)
    np.testing.assert_allclose(analysis.lower, stack.min(axis=0), rtol=0, atol=1e-9)
    worst_abs = np.abs(stack).max(axis=0)
    for row in analysis.joints:
        j = 0 if row["joint"] == "shoulder" else 1
        assert row["worst_peak"] == pytest.approx(worst_abs[:, j].max(), abs=1e-9)
        # the envelope's RMS bounds every build's RMS and is reached pose by pose
        assert row["worst_rms"] >= np.sqrt(np.mean(stack[:, :, j] ** 2, axis=1)).max() - 1e-12
        assert row["worst_peak"] > row["peak"]


def test_adjuster_travel_against_least_squares_per_corner(case):
    design, tau, corners = case
    analysis = analyse_tolerance(design, SPEC)
    step = 1e-6  # [m] the preload screw's turn in the finite difference
    nominal = list(LAWS)
    columns = []
    for s in range(2):  # ∂τ/∂t: shorten spring s's free length by t
        shifted = [(k, l0 - step if i == s else l0, f0) for i, (k, l0, f0) in enumerate(nominal)]
        columns.append(((tau(shifted) - design.evaluation.tau) / step).reshape(-1))
    A = np.stack(columns, axis=1)
    # each build restored to the nominal design: least squares on its change of the residual
    nominal_tau = design.evaluation.tau
    adjustments = np.array(
        [np.linalg.lstsq(A, -(r - nominal_tau).reshape(-1), rcond=None)[0] for _, r in corners.values()]
    )
    for s, row in enumerate(analysis.travel):
        # the analysis uses the nominal rate in the adjuster's column (δk·t is second order: ≤ 10 % of t here)
        assert row["high"] == pytest.approx(adjustments[:, s].max(), rel=0.1, abs=1e-5)
        assert row["low"] == pytest.approx(adjustments[:, s].min(), rel=0.1, abs=1e-5)
        assert row["travel"] > 0
        assert row["low"] < 0 < row["high"]  # the nominal build needs no turn, the corners turn both ways
    # after the adjustment the worst residual is smaller than before it
    for row in analysis.joints:
        assert row["adjusted_rms"] < row["worst_rms"]


def test_grade_box_of_a_coil_is_the_standard(case):
    """A helical extension spring under grade 2: ± 1.5 % on the rate, A_F(F_i) on the initial tension."""
    mechanism = case[0].problem.mechanism
    workspace = case[0].problem.workspace
    coil = sb.HelicalExtensionSpring(
        sb.Anchor("universe", (0.0, 0.0, 0.25)), sb.Anchor("link1", (0.3, 0.0, 0.0)), "coil",
        wire_diameter=0.002, mean_diameter=0.016, active_coils=40.0, initial_tension=8.0, keep_tension=False,
    )  # fmt: skip
    design = sb.EvaluatedDesign(sb.DesignProblem(mechanism, workspace, [coil]), np.zeros(0))
    analysis = analyse_tolerance(design, ToleranceSpec.from_record({"grade": 2}))
    (box,) = analysis.boxes
    assert box.d_rate == pytest.approx(0.015)
    # EN 15800 by hand, d = 2 mm, D = 16 mm (w/10 = 0.8), n = 40: α_F k_F + 1.5 % F_i
    bracket = -0.84 * 0.8**3 + 3.781 * 0.8**2 - 4.244 * 0.8 + 2.274
    alpha = 65.92 * 2.0**3.3 / 16.0**1.6 * bracket
    kf = 1 / (3 * 40**2) + 8 / (5 * 40) + 0.803
    assert box.d_tension == pytest.approx(alpha * kf + 0.015 * 8.0)
    assert box.d_free_length == 0.0


@pytest.mark.parametrize(
    ("record", "message"),
    [
        ({"grade": 4}, "tolerance.grade must be 1, 2 or 3"),
        ({"rate": -0.1}, "tolerance.rate must be a number in [0, 1)"),
        ({"rate": "ten"}, "tolerance.rate must be a number"),
        ({"free_length": float("nan")}, "tolerance.free_length must be a number ≥ 0"),
        ({"grade": 1, "rate": 0.1}, "not both"),
        ({"graed": 1}, "unknown key(s) 'graed'"),
        ({"adjuster_travel": 0}, "tolerance.adjuster_travel must be a positive number"),
        ({"robust": "yes"}, "tolerance.robust must be true or false"),
    ],
)
def test_bad_records(record, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
        ToleranceSpec.from_record(record)


def test_config_section_reaches_the_report(tmp_path):
    """A config's tolerance section: explicit ± and an adjuster bound, shown in the text report; a bad value
    is a one-line error naming the key."""
    from springbalance.io.config import config_from_dict
    from springbalance.results.report import result_table

    record = {
        "mechanism": {"urdf": str(URDF / "two_link_planar.urdf")},
        "workspace": {"kind": "grid", "n": 3, "ranges": {"shoulder": [-1, 1], "elbow": [-1, 1]}},
        "springs": [
            {
                "name": "s1", "type": "extension", "ideal": True, "keep_tension": False,
                "a": {"body": "universe", "point": [0, 0, 0.25]}, "b": {"body": "link1", "point": [0.3, 0, 0]},
                "stiffness": 900.0, "free_length": 0.12, "initial_tension": 10.0,
            }
        ],
        "tolerance": {"rate": 0.1, "initial_tension": 2.0, "adjuster_travel": 0.0001},
    }  # fmt: skip
    config = config_from_dict(record, tmp_path)
    assert config.tolerance == ToleranceSpec(grade=None, rate=0.1, initial_tension=2.0, adjuster_travel=0.0001)
    design = sb.DesignResult(config.problem, np.zeros(0), tolerance=config.tolerance)
    text = result_table(design)
    assert "Tolerances:" in text and "±10 %" in text and "EXCEEDED by s1" in text
    assert design.to_dict()["tolerance"]["spec"]["rate"] == 0.1
    with pytest.raises(InputError, match=r"tolerance\.grade must be 1, 2 or 3, got 5|tolerance.grade"):
        config_from_dict({**record, "tolerance": {"grade": 5}}, tmp_path)


def test_two_coils_side_by_side_share_the_turn_of_one():
    """Two springs of rate k/2 with anchors 1 mm apart act almost like one spring of rate k: turned together
    by t, they change the force by k t like its screw. Each one's travel is then about the single spring's,
    not a pair of huge opposite turns that cancel (what a plain pseudo-inverse of the nearly collinear
    columns gives)."""
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.from_array(mechanism, np.random.default_rng(3).uniform(-1.2, 1.2, size=(40, 2)))

    def spring(name, z, stiffness, tension):
        return sb.ExtensionSpring(
            sb.Anchor("universe", (0.0, 0.0, z)), sb.Anchor("link1", (0.3, 0.0, 0.0)), name,
            stiffness=stiffness, free_length=0.12, initial_tension=tension, keep_tension=False,
        )  # fmt: skip

    spec = ToleranceSpec.from_record({"rate": 0.1, "initial_tension": 3.0, "free_length": 0.004})
    single = sb.EvaluatedDesign(sb.DesignProblem(mechanism, workspace, [spring("one", 0.25, 900.0, 10.0)]), np.zeros(0))
    pair = [spring("a", 0.25, 450.0, 5.0), spring("b", 0.251, 450.0, 5.0)]
    double = sb.EvaluatedDesign(sb.DesignProblem(mechanism, workspace, pair), np.zeros(0))
    one = analyse_tolerance(single, spec).travel[0]["travel"]
    for row in analyse_tolerance(double, spec).travel:
        assert 0.5 * one < row["travel"] < 2.0 * one, (row, one)
