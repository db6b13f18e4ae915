"""R4 of docs/reference_cases.md: the self-regulating 1-DOF balancer of Franchetti, Boschetti & Lenzo (2021).

urdf/self_regulating_link.urdf: link m = 3 kg, centre of mass at c = 0.2 m along the link-frame
x axis; zero-free-length spring k = 981 N/m from the world point (0, 0, a = 0.1 m) above the
pivot to the link point (b, 0, 0), which slides on the link (segment from the pivot to w).
g = 9.81. Published: k a b = m c g gives b = 0.06 m for the bare link; a payload of 1 kg at
w = 0.35 m is balanced by moving the anchor out by Δb = Δm w g / (k a) = 35 mm (b = 0.095 m);
with the anchor travel ending at w, the largest payload is k a (w - b) / (w g).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf" / "self_regulating_link.urdf"
M, C, K, A, G = 3.0, 0.2, 981.0, 0.1, 9.81


def adjustable_design(mechanism, workspace, w, scenarios):
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, A)), sb.Anchor("link1", sb.Segment((0, 0, 0), (w, 0, 0))), stiffness=K
    )
    problem = sb.DesignProblem(mechanism, workspace, [spring], scenarios=scenarios, per_scenario=["s1.b"])
    return sb.solve(problem, starts=1)


@pytest.fixture(scope="module")
def setup():
    mechanism = sb.Mechanism.from_urdf(URDF, gravity=G)
    workspace = sb.Workspace.grid(mechanism, 145)  # full turn, every 2.5°
    return mechanism, workspace


def test_r4_anchor_moves_35_mm_for_1_kg_at_035_m(setup):
    mechanism, workspace = setup
    w = 0.35
    scenarios = [sb.Scenario("bare"), sb.Scenario("1 kg at 0.35 m", [sb.Payload("link1", 1.0, (w, 0, 0))])]
    result = adjustable_design(mechanism, workspace, w, scenarios)
    per_scenario = result.scenario_results()
    b = [record.spring("s1")["b"]["point"][0] for record in per_scenario]
    peaks = [record.metrics()["joints"][0]["peak_after"] for record in per_scenario]
    unbalanced = (M * C + 1.0 * w) * G  # peak gravity torque with the payload [N·m]
    print(f"[R4] b (bare)        project {b[0]:.6f} m   published 0.06 m")
    print(f"[R4] b (1 kg)        project {b[1]:.6f} m   published 0.095 m")
    print(f"[R4] Δb              project {1e3 * (b[1] - b[0]):.4f} mm  published 35 mm")
    print(f"[R4] peak residuals  project {peaks[0]:.3g}, {peaks[1]:.3g} N·m   published 0")
    assert b[0] == pytest.approx(M * C * G / (K * A), abs=1e-9) and b[0] == pytest.approx(0.06, abs=1e-9)
    assert b[1] == pytest.approx(0.095, abs=1e-9)
    assert b[1] - b[0] == pytest.approx(1.0 * w * G / (K * A), abs=1e-9)  # Δb = Δm w g / (k a)
    assert max(peaks) < 1e-9 * unbalanced
    # the scenarios share the spring and differ only in the slider: the design has two anchor copies
    assert sorted(result.variables) == ["s1.b.s[1 kg at 0.35 m]", "s1.b.s[bare]"]


@pytest.mark.parametrize("w", [0.35, 0.30])
def test_r4_largest_payload_for_anchor_travel_up_to_w(setup, w, tmp_path):
    mechanism, workspace = setup
    result = adjustable_design(mechanism, workspace, w, [sb.Scenario("bare")])
    study = sb.payload_range(result, "link1", (w, 0, 0), max_residual=1e-6)
    b = M * C * G / (K * A)
    published = K * A * (w - b) / (w * G)
    print(f"[R4] largest payload (w = {w} m)  project {study.max_payload:.6f} kg   published {published:.6f} kg")
    assert study.max_payload == pytest.approx(published, rel=1e-6)
    # below it the anchor follows b + Δm w g/(k a) with zero residual; above it the anchor sits at w
    for row in study.rows:
        expected = min(b + row.mass * w * G / (K * A), w)
        assert row.anchors["s1.b"][0] == pytest.approx(expected, abs=1e-7)
        assert row.balanced == (row.mass <= published)
        if row.mass > published:  # saturated slider: the excess payload's moment is left over
            assert row.peak == pytest.approx((row.mass - published) * G * w, rel=1e-6)
    figure = study.plot(tmp_path / "payload_range")
    assert (tmp_path / "payload_range.png").stat().st_size > 0 and figure.axes
    assert "largest payload balanced" in study.table()


def test_r4_fixed_design_residual_grows_with_payload(setup, tmp_path):
    mechanism, workspace = setup
    w = 0.35
    result = adjustable_design(mechanism, workspace, w, [sb.Scenario("bare")])
    sweep = sb.residual_vs_payload(result, "link1", [0.0, 0.5, 1.0, 2.0], (w, 0, 0))
    # the bare design stays balanced; a payload Δm at w leaves Δm g w cos(theta): peak Δm g w
    assert sweep.peak[0] < 1e-9
    np.testing.assert_allclose(sweep.peak[1:], np.array([0.5, 1.0, 2.0]) * G * w, rtol=1e-9)
    np.testing.assert_allclose(sweep.rms[1:], np.array([0.5, 1.0, 2.0]) * G * w / np.sqrt(2), rtol=2e-2)
    figure = sweep.plot(tmp_path / "residual")
    assert (tmp_path / "residual.svg").stat().st_size > 0 and figure.axes
    assert "payload [kg]" in sweep.table()


def test_r4_each_load_case_keeps_its_own_constant_potential(setup, tmp_path):
    """With the slider set per payload both load cases are exactly balanced; each has a constant total
    potential of its own (the payload's weight shifts the level), and the reports say so per scenario."""
    mechanism, workspace = setup
    w = 0.35
    scenarios = [sb.Scenario("bare"), sb.Scenario("1 kg at 0.35 m", [sb.Payload("link1", 1.0, (w, 0, 0))])]
    result = adjustable_design(mechanism, workspace, w, scenarios)
    balance = result.exact_balance()
    assert balance["exact"]
    assert balance["potential_spread"] < 1e-9 * M * C * G
    assert len(balance["scenario_potentials"]) == 2
    assert "constant within each scenario" in result.table()
    report_folder = tmp_path / "report"
    result.report(report_folder, scene=False)
    page = (report_folder / "report.html").read_text()
    assert "<h2>Scenarios</h2>" in page and "1 kg at 0.35 m" in page and "Exactly balanced" in page
