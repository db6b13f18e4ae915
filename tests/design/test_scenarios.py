"""Scenarios: payloads and scaled link masses, shared and per-scenario variables, payload studies.

Physics asserted here, not solver output: a point mass m at lever x on a link adds m g x cos q to
the gravity torque; a scale β multiplies it by β; a design with more freedom (per-payload slider)
cannot be worse than one without (robust fixed), which cannot be worse in the worst case than a
design that ignores the payload (tuned for 0 kg). benchmarks/bench_payload.py prints the numbers.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

import springbalance as sb
from springbalance import ConfigError, InputError
from springbalance.io.config import load_config

URDF = Path(__file__).resolve().parents[2] / "urdf"
G = 9.81


@pytest.fixture(scope="module")
def link():
    mechanism = sb.Mechanism.from_urdf(URDF / "self_regulating_link.urdf", gravity=G)
    return mechanism, sb.Workspace.grid(mechanism, 37)


def r4_spring():
    return sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", sb.Segment((0, 0, 0), (0.35, 0, 0))), stiffness=981.0
    )


# ---------------------------------------------------------------------- scenario mechanics
def test_payload_and_mass_scale_change_gravity_only(link):
    mechanism, workspace = link
    q = workspace.joint_values[:, 0]
    scenarios = [
        sb.Scenario("bare"),
        sb.Scenario("2 kg at 0.3 m", [sb.Payload("link1", 2.0, (0.3, 0, 0))]),
        sb.Scenario("half limb", mass_scale=0.5),
        sb.Scenario(
            "half limb + 1 kg", [{"body": "link1", "mass": 1.0, "point": [0.1, 0, 0]}], mass_scale={"link1": 0.5}
        ),
    ]
    problem = sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=scenarios, per_scenario=["s1.b"])
    gravity = problem.workspace.kinematics().gravity_torque[:, 0].reshape(4, -1)
    bare = 3.0 * 0.2 * G * np.cos(q)  # m c g cos q [N·m]
    np.testing.assert_allclose(gravity[0], bare, atol=1e-12)
    np.testing.assert_allclose(gravity[1], bare + 2.0 * 0.3 * G * np.cos(q), atol=1e-12)
    np.testing.assert_allclose(gravity[2], 0.5 * bare, atol=1e-12)
    np.testing.assert_allclose(gravity[3], 0.5 * bare + 1.0 * 0.1 * G * np.cos(q), atol=1e-12)
    # the user's mechanism is untouched, and kinematics are shared
    np.testing.assert_allclose(workspace.kinematics().gravity_torque[:, 0], bare, atol=1e-12)
    assert problem.workspace.size == 4 * workspace.size and problem.base_workspace is workspace
    assert problem.variables.names == [f"s1.b.s[{s.name}]" for s in scenarios]


def test_single_scenario_path_is_unchanged(link):
    mechanism, workspace = link
    plain = sb.DesignProblem(mechanism, workspace, [r4_spring()])
    assert plain.variables.names == ["s1.b.s"] and plain.scenarios == [] and plain.workspace is workspace
    one = sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=[sb.Scenario("x")])
    assert plain.model.data_size == one.model.data_size - 1  # one scenario adds only its selector row


def test_bad_scenario_input_is_named(link):
    mechanism, workspace = link
    with pytest.raises(InputError, match="per-scenario variable 's1.c' matches no design variable"):
        sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=[sb.Scenario("a")], per_scenario=["s1.c"])
    with pytest.raises(InputError, match="need scenarios"):
        sb.DesignProblem(mechanism, workspace, [r4_spring()], per_scenario=["s1.b"])
    with pytest.raises(InputError, match="aggregate"):
        sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=[sb.Scenario("a")], aggregate="mean")
    with pytest.raises(InputError, match="unknown payload body 'hand'"):
        sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=[sb.Scenario("a", [sb.Payload("hand", 1)])])
    with pytest.raises(InputError, match="unique"):
        sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=[sb.Scenario("a"), sb.Scenario("a")])
    with pytest.raises(InputError, match="mass must be"):
        sb.Payload("link1", -1.0)


def test_shared_stiffness_with_per_scenario_anchor_balances_each_payload(link):
    """k free and shared, anchor per scenario: k a b_s = (m c + Δm_s w) g for each s has a solution
    for any k with b_s in the travel; every scenario ends exactly balanced."""
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)),
        sb.Anchor("link1", sb.Segment((0, 0, 0), (0.35, 0, 0))),
        stiffness=sb.Free(500, 3000),
    )
    scenarios = sb.payload_scenarios("link1", [0.0, 1.0, 2.0], (0.35, 0, 0))
    problem = sb.DesignProblem(mechanism, workspace, [spring], scenarios=scenarios, per_scenario=["s1.b"])
    result = sb.solve(problem, starts=2)
    k = result.variables["s1.stiffness"]
    for row in problem.scenario_table(result.x):
        b = 0.35 * row["variables"]["s1.b.s"]
        assert k * 0.1 * b == pytest.approx((3.0 * 0.2 + row["payload"] * 0.35) * G, rel=1e-6)
        assert row["peak"] < 1e-6
    assert "Scenarios (3" in result.table()


def test_worst_case_aggregate_balances_the_worst_scenario(link):
    """One fixed spring for 0 and 2 kg: the worst-case rms design has the smaller worst-scenario rms,
    and for this linear problem it equalises the two scenarios' rms (b halfway: the payload's moment
    is split evenly)."""
    mechanism, workspace = link
    scenarios = sb.payload_scenarios("link1", [0.0, 2.0], (0.35, 0, 0))
    designs = {
        aggregate: sb.solve(
            sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=scenarios, aggregate=aggregate), starts=1
        )
        for aggregate in ("sum", "worst")
    }
    worst = {
        aggregate: max(row["rms"] for row in result.problem.scenario_table(result.x))
        for aggregate, result in designs.items()
    }
    assert worst["worst"] <= worst["sum"] * (1 + 1e-6)
    rms = [row["rms"] for row in designs["worst"].problem.scenario_table(designs["worst"].x)]
    assert rms[0] == pytest.approx(rms[1], rel=1e-4)
    b = designs["worst"].spring("s1")["b"]["point"][0]
    assert b == pytest.approx((3.0 * 0.2 + 1.0 * 0.35) * G / (981 * 0.1), rel=1e-4)


def test_pe_variance_is_taken_per_scenario(link):
    """Each scenario's potential has its own constant: pe_variance with per-scenario anchors reaches
    zero (exact balance in each scenario) although the constants differ."""
    mechanism, workspace = link
    scenarios = sb.payload_scenarios("link1", [0.0, 1.0], (0.35, 0, 0))
    problem = sb.DesignProblem(
        mechanism, workspace, [r4_spring()], objective="pe_variance", scenarios=scenarios, per_scenario=["s1.b"]
    )
    result = sb.solve(problem, starts=1)
    b = [0.35 * v for v in result.x]
    assert b == pytest.approx([0.06, 0.095], abs=1e-6)


def test_scenario_design_saves_and_loads(link, tmp_path):
    mechanism, workspace = link
    scenarios = [sb.Scenario("bare"), sb.Scenario("1 kg", [sb.Payload("link1", 1.0, (0.35, 0, 0))])]
    result = sb.solve(
        sb.DesignProblem(mechanism, workspace, [r4_spring()], scenarios=scenarios, per_scenario=["s1.b"]), starts=1
    )
    path = result.save(tmp_path / "design.json")
    record = json.loads(path.read_text())
    assert record["scenarios"]["per_scenario"] == ["s1.b"] and len(record["workspace"]["joint_values"]) == 37
    loaded = sb.DesignResult.load(path)
    assert loaded.variables == result.variables
    np.testing.assert_allclose(loaded.evaluation.tau, result.evaluation.tau, atol=1e-12)


# ---------------------------------------------------------------------- config
R4_CONFIG = {
    "mechanism": {"urdf": str(URDF / "self_regulating_link.urdf"), "gravity": G},
    "workspace": {"kind": "grid", "n": 37},
    "springs": [
        {
            "name": "s1",
            "type": "zero_free_length",
            "a": {"body": "universe", "point": [0, 0, 0.1]},
            "b": {"body": "link1", "segment": {"start": [0, 0, 0], "end": [0.35, 0, 0]}},
            "stiffness": 981,
        }
    ],
    "scenarios": {
        "per_scenario": ["s1.b"],
        "cases": [
            {"name": "bare"},
            {"name": "1 kg", "payloads": [{"body": "link1", "mass": 1, "point": [0.35, 0, 0]}]},
        ],
    },
    "solve": {"starts": 1},
}


def write_config(tmp_path, record):
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(record))
    return path


def test_config_scenarios_section(tmp_path):
    config = load_config(write_config(tmp_path, R4_CONFIG))
    assert [s.name for s in config.problem.scenarios] == ["bare", "1 kg"]
    result = config.solve()
    assert [0.35 * v for v in result.x] == pytest.approx([0.06, 0.095], abs=1e-9)
    ranged = {
        **R4_CONFIG,
        "scenarios": {
            "payload_range": {"body": "link1", "point": [0.35, 0, 0], "masses": [0, 1, 2]},
            "per_scenario": ["s1.b"],
            "aggregate": "sum",
        },
    }
    config = load_config(write_config(tmp_path, ranged))
    assert [s.payload_mass for s in config.problem.scenarios] == [0, 1, 2]


@pytest.mark.parametrize(
    "scenarios, message",
    [
        ({"cases": [{"name": "a"}], "extra": 1}, "scenarios: unknown key 'extra'"),
        ({"cases": [{"name": "a", "payload": []}]}, r"scenarios.cases\[0\]: unknown key 'payload'"),
        (
            {"cases": [{"name": "a", "payloads": [{"body": "hand", "mass": 1}]}]},
            r"payloads\[0\].body: unknown body 'hand'",
        ),
        (
            {"cases": [{"name": "a", "payloads": [{"body": "link1", "mass": 1, "where": [0, 0, 0]}]}]},
            "unknown key 'where'",
        ),
        ({"payload_range": {"body": "link1", "masses": [0, -1]}}, "masses: expected a non-empty list of masses"),
        ({"cases": [{"name": "a"}], "payload_range": {"body": "link1", "masses": [1]}}, "exactly one of 'cases'"),
        ({"cases": [{"name": "a"}], "aggregate": "mean"}, "aggregate: unknown aggregate 'mean'"),
    ],
)
def test_config_scenarios_errors(tmp_path, scenarios, message):
    with pytest.raises(ConfigError, match=message):
        load_config(write_config(tmp_path, {**R4_CONFIG, "scenarios": scenarios}))


# ---------------------------------------------------------------------- two-link payload range (must hold 2)
MASSES = [0.0, 1.0, 2.0]


def two_link_springs():
    """Ground → link1 (slider along link1) and ground → link2 (slider along link2), zero free length."""
    return [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([-0.1, 0, 0.02], [0.1, 0, 0.3])),
            sb.Anchor("link1", sb.Segment([0.02, 0, 0], [0.5, 0, 0])),
            stiffness=sb.Free(0, 5000),
            name="shoulder_spring",
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([-0.3, 0, -0.1], [0.3, 0, 0.6])),
            sb.Anchor("link2", sb.Segment([0.02, 0, 0], [0.4, 0, 0])),
            stiffness=sb.Free(0, 5000),
            name="elbow_spring",
        ),
    ]


def worst_peak(problem, x):
    return max(row["peak"] for row in problem.scenario_table(x))


def test_two_link_slider_beats_robust_beats_tuned_for_no_payload():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.grid(
        mechanism, {"shoulder": 9, "elbow": 9}, ranges={"shoulder": (-90, 90), "elbow": (-120, 120)}, degrees=True
    )
    payloads = sb.payload_scenarios("tool", MASSES)
    tuned = sb.solve(sb.DesignProblem(mechanism, workspace, two_link_springs(), objective="peak"), starts=4)
    robust_problem = sb.DesignProblem(mechanism, workspace, two_link_springs(), objective="peak", scenarios=payloads)
    robust = sb.solve(robust_problem, starts=4)
    slider_problem = sb.DesignProblem(
        mechanism,
        workspace,
        two_link_springs(),
        objective="peak",
        scenarios=payloads,
        per_scenario=["shoulder_spring.b", "elbow_spring.b"],
    )
    slider = sb.solve(slider_problem, starts=4)
    tuned_sweep = sb.residual_vs_payload(tuned, "tool", MASSES)
    robust_sweep = sb.residual_vs_payload(robust, "tool", MASSES)
    numbers = {
        "slider": worst_peak(slider_problem, slider.x),
        "robust": worst_peak(robust_problem, robust.x),
        "tuned@2kg": tuned_sweep.peak[-1],
        "tuned@0kg": tuned_sweep.peak[0],
    }
    print("[payload 0-2 kg] worst-case peak [N·m]: " + ", ".join(f"{k} {v:.4f}" for k, v in numbers.items()))
    # the robust design evaluated by the sweep agrees with its own problem
    assert max(robust_sweep.peak) == pytest.approx(numbers["robust"], rel=1e-9)
    # orderings (must hold 2)
    assert numbers["slider"] < numbers["robust"]
    assert numbers["robust"] < numbers["tuned@2kg"] and numbers["slider"] < numbers["tuned@2kg"]
    # the design tuned for no payload is the best one there, and degrades with the payload
    assert numbers["tuned@0kg"] < numbers["slider"] and np.all(np.diff(tuned_sweep.peak) > 0)
    # the slider moves out along link1 as the payload grows (more moment to carry)
    shoulder = [row["variables"]["shoulder_spring.b.s"] for row in slider_problem.scenario_table(slider.x)]
    assert shoulder[0] < shoulder[1] < shoulder[2]


# ---------------------------------------------------------------------- command line
def test_cli_designs_scenarios_and_reports_the_payload_range(tmp_path, capsys):
    from springbalance.cli import main

    config = write_config(tmp_path, R4_CONFIG)
    out = tmp_path / "design.json"
    assert main(["design", str(config), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "Scenarios (2" in text and "1 kg" in text
    assert main(["evaluate", str(out)]) == 0
    assert "Scenarios (2" in capsys.readouterr().out
    assert (
        main(
            [
                "payload-range",
                str(out),
                "--body",
                "link1",
                "--point",
                "0.35",
                "0",
                "0",
                "--max-residual",
                "1e-6",
                "--masses",
                "0",
                "1",
                "--plot",
                str(tmp_path / "range"),
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    largest = float(text.split("largest payload balanced:")[1].split()[0])
    assert largest == pytest.approx(981 * 0.1 * (0.35 - 0.06) / (0.35 * G), rel=1e-5)  # k a (w - b)/(w g)
    assert (tmp_path / "range.png").exists()
    assert main(["payload-range", str(out), "--body", "hand"]) == 2
    assert "unknown body 'hand'" in capsys.readouterr().err


def test_example_config_reproduces_r4():
    config = load_config(Path(__file__).resolve().parents[2] / "examples" / "self_regulating_link.yaml")
    result = config.solve(progress=False)
    b = [scenario.spring("s1")["b"]["point"][0] for scenario in result.scenario_results()]
    assert b == pytest.approx([3.0 * 0.2 * G / (981 * 0.1), 0.095], abs=1e-9)
