"""Design results: save/load round trip, residual torque, metrics against Pinocchio."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf"
OBJECTIVE_NAMES = {"rms", "peak", "pe_variance", "energy", "joint_peaks", "peak_then_joints"}


@pytest.fixture(scope="module")
def arm():
    return sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")


def _springs():
    return [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([0, 0, 0.05], [0, 0, 0.3])),
            sb.Anchor("link1", sb.Segment((0.05, 0, 0), (0.45, 0, 0))),
            name="shoulder_spring",
            stiffness=sb.Free(0, 3000),
        ),
        sb.ExtensionSpring(
            sb.Anchor("link1", (0.1, 0, 0.05)),
            sb.Anchor("link2", sb.Free([0.02, 0, 0], [0.3, 0, 0])),
            name="elbow_spring",
            stiffness=sb.Free(0, 2000),
            free_length=sb.Free(0.05, 0.3),
            initial_tension=sb.Free(0, 20),
            keep_tension=False,
        ),
    ]


@pytest.fixture(scope="module")
def solved(arm):
    workspace = sb.Workspace.grid(arm, 9, couplings=[sb.Coupling.parse("elbow - shoulder", -120, 60, degrees=True)])
    problem = sb.DesignProblem(arm, workspace, _springs(), objective="rms", weights={"elbow": 2.0})
    return sb.solve(problem, starts=2, seed=1)


def test_solution_improves_on_gravity(solved):
    metrics = solved.metrics()
    # A hand design is available: the shoulder ZFL spring with k a b = 1.25 g cancels link 1's
    # own moment 1.25 g cos(s) (docs/model.md §9) and the elbow spring idles (k = F0 = 0). What is
    # left is the forearm moment 0.4 g cos(s + e) on both joints (elbow weight 2). The
    # optimum can only be better.
    s, e = solved.problem.workspace.joint_values.T
    forearm = 9.81 * 0.4 * np.cos(s + e)
    hand_design_rms = np.sqrt(np.mean(np.concatenate([forearm, 2 * forearm]) ** 2))
    assert metrics["objectives"]["rms"]["after"] <= hand_design_rms * (1 + 1e-9)
    assert metrics["objectives"]["rms"]["after"] < metrics["objectives"]["rms"]["before"]
    for row in metrics["joints"]:
        assert row["rms_after"] < row["rms_before"]


def test_save_load_round_trip_is_exact(solved, tmp_path):
    path = solved.save(tmp_path / "design.json")
    assert json.loads(path.read_text())["format"].startswith("springbalance-design")
    loaded = sb.DesignResult.load(path)
    assert loaded.problem.variables.names == solved.problem.variables.names
    assert loaded.variables == solved.variables  # exact float equality
    np.testing.assert_array_equal(loaded.x, solved.x)
    assert loaded.springs == solved.springs
    assert loaded.metrics() == solved.metrics()  # every number identical
    np.testing.assert_array_equal(loaded.residual_torque(), solved.residual_torque())
    np.testing.assert_array_equal(loaded.problem.workspace.joint_values, solved.problem.workspace.joint_values)
    np.testing.assert_array_equal(loaded.problem.weights, solved.problem.weights)
    assert loaded.problem.objective.name == "rms"
    # Saving the loaded design again writes the same variables and metrics.
    again = json.loads(loaded.save(tmp_path / "again.json").read_text())
    first = json.loads(path.read_text())
    assert again["variables"] == first["variables"]
    assert again["metrics"] == first["metrics"]
    assert again["design"] == first["design"]


def test_save_load_robot_with_gravity_override(tmp_path):
    mechanism = sb.Mechanism.from_robot("ur5", gravity=9.8)
    workspace = sb.Workspace.random(mechanism, 10, seed=4)
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", (0.05, 0.1, 0.4)),
        sb.Anchor("upper_arm_link", (0, 0.05, 0.2)),
        stiffness=sb.Free(0, 4000),
        free_length=0.1,
        keep_tension=False,
    )
    problem = sb.DesignProblem(mechanism, workspace, [spring], objective="peak")
    result = sb.DesignResult(problem, [1234.5678901234567])
    loaded = sb.DesignResult.load(result.save(tmp_path / "ur5.json"))
    np.testing.assert_array_equal(loaded.problem.mechanism.gravity, [0, 0, -9.8])
    assert loaded.problem.objective.name == "peak"
    assert loaded.variables == {"s1.stiffness": 1234.5678901234567}
    assert _same(loaded.metrics(), result.metrics())


def _same(a, b) -> bool:
    """Equality that treats NaN as equal to NaN (the energy objective of an unordered workspace)."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and np.isnan(a):
        return isinstance(b, float) and np.isnan(b)
    return a == b


def test_load_errors_name_the_file(tmp_path):
    missing = tmp_path / "missing_design.json"
    with pytest.raises(sb.InputError, match="missing_design.json"):
        sb.DesignResult.load(missing)
    garbage = tmp_path / "garbage_design.json"
    garbage.write_text("{not json")
    with pytest.raises(sb.InputError, match="garbage_design.json"):
        sb.DesignResult.load(garbage)
    other = tmp_path / "other_format.json"
    other.write_text(json.dumps({"format": "something-else"}))
    with pytest.raises(sb.InputError, match="other_format.json"):
        sb.DesignResult.load(other)


def test_residual_torque_at_given_configurations(solved, arm):
    rows = np.array([[0.1, -0.3], [1.2, 0.4], [-1.0, -2.0], [0.0, 0.0]])
    tau = solved.residual_torque(rows)
    # Same springs, same values, on a workspace made of exactly these rows.
    problem = sb.DesignProblem(arm, sb.Workspace.from_array(arm, rows), _springs())
    expected = problem.evaluate(solved.x).tau
    np.testing.assert_allclose(tau, expected, rtol=1e-13, atol=1e-13)
    # Degrees are accepted.
    np.testing.assert_allclose(solved.residual_torque(np.rad2deg(rows), degrees=True), expected, rtol=1e-12, atol=1e-12)
    # One row works too.
    np.testing.assert_allclose(solved.residual_torque(rows[1]), expected[1:2], rtol=1e-13, atol=1e-13)
    # On the design's own workspace, the default is the stored evaluation.
    np.testing.assert_array_equal(solved.residual_torque(), solved.problem.evaluate(solved.x).tau)
    # And re-evaluating on the workspace's configurations reproduces it.
    np.testing.assert_allclose(
        solved.residual_torque(solved.problem.workspace.joint_values), solved.residual_torque(), rtol=1e-12, atol=1e-12
    )


def test_metrics_cover_every_joint_and_objective(solved, arm):
    metrics = solved.metrics()
    assert [row["joint"] for row in metrics["joints"]] == arm.joint_names
    assert set(metrics["objectives"]) == OBJECTIVE_NAMES
    assert metrics["optimised"] == "rms"
    assert metrics["samples"] == solved.problem.workspace.size
    for name in OBJECTIVE_NAMES:
        row = metrics["objectives"][name]
        assert np.isfinite(row["before"]) and np.isfinite(row["after"])
    table = solved.table()
    for name in arm.joint_names + sorted(OBJECTIVE_NAMES) + ["shoulder_spring", "elbow_spring"]:
        assert name in table


def test_metrics_match_pinocchio_gravity(solved, arm):
    """Before = bare mechanism (gravity only), computed here with Pinocchio; after = residual torque."""
    workspace = solved.problem.workspace
    weights = np.array([1.0, 2.0])
    model, data = arm.model, arm.model.createData()
    gravity = np.array([pin.computeGeneralizedGravity(model, data, q) for q in workspace.configurations])
    potential = np.array([pin.computePotentialEnergy(model, data, q) for q in workspace.configurations])
    after = solved.residual_torque()
    metrics = solved.metrics()
    for j, row in enumerate(metrics["joints"]):
        assert row["peak_before"] == pytest.approx(np.max(np.abs(gravity[:, j])), rel=1e-12)
        assert row["rms_before"] == pytest.approx(np.sqrt(np.mean(gravity[:, j] ** 2)), rel=1e-12)
        assert row["peak_after"] == pytest.approx(np.max(np.abs(after[:, j])), rel=1e-12)
        assert row["rms_after"] == pytest.approx(np.sqrt(np.mean(after[:, j] ** 2)), rel=1e-12)
        assert row["rms_reduction_percent"] == pytest.approx(100 * (1 - row["rms_after"] / row["rms_before"]), rel=1e-9)
    objectives = metrics["objectives"]
    steps = np.abs(np.diff(workspace.joint_values, axis=0))
    assert objectives["rms"]["before"] == pytest.approx(np.sqrt(np.mean((gravity * weights) ** 2)), rel=1e-12)
    assert objectives["peak"]["before"] == pytest.approx(np.max(np.abs(gravity * weights)), rel=1e-12)
    assert objectives["pe_variance"]["before"] == pytest.approx(np.var(potential), rel=1e-10)
    assert objectives["energy"]["before"] == pytest.approx(np.sum(np.abs(gravity[:-1] * weights) * steps), rel=1e-12)
    assert objectives["rms"]["after"] == pytest.approx(np.sqrt(np.mean((after * weights) ** 2)), rel=1e-12)
    assert objectives["peak"]["after"] == pytest.approx(np.max(np.abs(after * weights)), rel=1e-12)
    assert objectives["energy"]["after"] == pytest.approx(np.sum(np.abs(after[:-1] * weights) * steps), rel=1e-12)
    # The two-link arm's gravity torque in closed form (masses 2, 1 + 0.5 tool), as a check of the check.
    s, e = workspace.joint_values.T
    np.testing.assert_allclose(gravity[:, 1], 9.81 * 0.4 * np.cos(s + e), rtol=0, atol=1e-12)
    np.testing.assert_allclose(gravity[:, 0], 9.81 * 1.25 * np.cos(s) + gravity[:, 1], rtol=0, atol=1e-12)


def test_springs_can_be_reused_in_another_problem():
    """Building a problem must not change the caller's springs (unnamed springs get names).

    A spring object used unnamed in one problem and then placed second in another problem
    beside a new unnamed spring must still be accepted.
    """
    r2 = sb.Mechanism.from_urdf(URDF / "single_link_r2.urdf")
    workspace = sb.Workspace.grid(r2, 5)
    first = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.2, 0, 0)), stiffness=100.0
    )
    second = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.2)), sb.Anchor("link1", (0.1, 0, 0)), stiffness=50.0
    )
    alone = sb.DesignProblem(r2, workspace, [first]).evaluate(np.zeros(0)).tau
    both = sb.DesignProblem(r2, workspace, [second, first]).evaluate(np.zeros(0)).tau
    # ZFL springs from (0, 0, a) to (b, 0, 0) each add -k a b cos q.
    theta = workspace.joint_values[:, 0]
    np.testing.assert_allclose(both[:, 0] - alone[:, 0], -50.0 * 0.2 * 0.1 * np.cos(theta), rtol=0, atol=1e-12)
