"""Mechanisms: the ways to build one, gravity, joint kinds, errors that name the culprit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from physics_helpers import ReferencePotential, RefSpring

URDF = Path(__file__).resolve().parents[2] / "urdf"
R2 = URDF / "single_link_r2.urdf"

INERTIA = '<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/>'


def _link(name, mass=None, com=(0, 0, 0)):
    if mass is None:
        return f'<link name="{name}"/>'
    xyz = " ".join(str(v) for v in com)
    return (
        f'<link name="{name}"><inertial><origin xyz="{xyz}" rpy="0 0 0"/><mass value="{mass}"/>'
        f"{INERTIA}</inertial></link>"
    )


def _joint(name, kind, parent, child, xyz=(0, 0, 0), axis=(0, -1, 0), limits=(-3.0, 3.0)):
    origin = " ".join(str(v) for v in xyz)
    axis_text = " ".join(str(v) for v in axis)
    limit = (
        f'<limit lower="{limits[0]}" upper="{limits[1]}" effort="100" velocity="1"/>' if kind != "continuous" else ""
    )
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{origin}" rpy="0 0 0"/><axis xyz="{axis_text}"/>{limit}</joint>'
    )


def _robot(name, *parts):
    return f'<?xml version="1.0"?><robot name="{name}">{"".join(parts)}</robot>'


# ---------------------------------------------------------------------- constructors
def test_from_urdf_path():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    assert mechanism.joint_names == ["shoulder", "elbow"]
    assert mechanism.nv == 2
    assert [j.kind for j in mechanism.joints] == ["revolute", "revolute"]
    assert mechanism.joint("elbow").lower == pytest.approx(-5 * np.pi / 6)
    assert {"universe", "base", "link1", "link2", "tool"} <= set(mechanism.body_names)
    np.testing.assert_array_equal(mechanism.gravity, [0, 0, -9.81])
    assert mechanism.is_ground("base") and mechanism.is_ground("universe")
    assert not mechanism.is_ground("tool")
    # Also accepts a str path.
    assert sb.Mechanism.from_urdf(str(URDF / "two_link_planar.urdf")).joint_names == ["shoulder", "elbow"]


def test_from_urdf_string_equals_file():
    text = (URDF / "two_link_planar.urdf").read_text()
    from_text = sb.Mechanism.from_urdf_string(text)
    from_file = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    assert from_text.joint_names == from_file.joint_names
    values = [[0.3, -1.0], [-1.2, 2.0]]
    np.testing.assert_array_equal(
        sb.Workspace.from_array(from_text, values).kinematics().gravity_torque,
        sb.Workspace.from_array(from_file, values).kinematics().gravity_torque,
    )
    # Gravity torque of the planar arm, closed form (masses 2, 1 + 0.5 tool; COMs 0.25, 0.2, tip 0.4).
    s, e = np.array(values).T
    g = 9.81
    elbow = g * (1.0 * 0.2 + 0.5 * 0.4) * np.cos(s + e)
    shoulder = g * (2.0 * 0.25 + 1.5 * 0.5) * np.cos(s) + elbow
    np.testing.assert_allclose(
        sb.Workspace.from_array(from_text, values).kinematics().gravity_torque,
        np.column_stack([shoulder, elbow]),
        rtol=1e-12,
    )


def test_from_robot_name():
    mechanism = sb.Mechanism.from_robot("ur5")
    assert mechanism.nv == 6
    assert "upper_arm_link" in mechanism.body_names
    assert mechanism.source["kind"] == "robot" and mechanism.source["robot"] == "ur5"


def test_unknown_robot_name_suggests_close_names():
    with pytest.raises(sb.InputError) as error:
        sb.Mechanism.from_robot("ur55")
    message = str(error.value)
    assert "unknown example-robot-data robot 'ur55'; did you mean 'ur5'?" in message
    assert "`springbalance robots`" in message
    for name in ("panda", "double_pendulum"):  # not the whole list of names
        assert name not in message


def test_from_model_copies():
    model = pin.buildModelFromUrdf(str(R2))
    mechanism = sb.Mechanism.from_model(model, gravity=9.8)
    np.testing.assert_array_equal(model.gravity.linear, [0, 0, -9.81])  # the caller's model is untouched
    np.testing.assert_array_equal(mechanism.gravity, [0, 0, -9.8])


# ---------------------------------------------------------------------- gravity
def test_gravity_override_scalar():
    mechanism = sb.Mechanism.from_urdf(R2, gravity=9.8)
    np.testing.assert_array_equal(mechanism.gravity, [0, 0, -9.8])
    workspace = sb.Workspace.from_array(mechanism, [[0.0], [np.pi / 3]])
    np.testing.assert_allclose(
        workspace.kinematics().gravity_torque[:, 0], 9.8 * 0.25 * np.cos([0.0, np.pi / 3]), rtol=1e-12
    )
    robot = sb.Mechanism.from_robot("ur5", gravity=1.62)
    np.testing.assert_array_equal(robot.gravity, [0, 0, -1.62])


def test_gravity_override_vector():
    # Gravity along -x: potential m g x_com = m g c cos q, holding torque -m g c sin q.
    mechanism = sb.Mechanism.from_urdf(R2, gravity=[-9.81, 0.0, 0.0])
    np.testing.assert_array_equal(mechanism.gravity, [-9.81, 0, 0])
    theta = np.array([0.0, np.pi / 2, -np.pi / 4])
    workspace = sb.Workspace.from_array(mechanism, theta[:, None])
    np.testing.assert_allclose(
        workspace.kinematics().gravity_torque[:, 0], -9.81 * 0.25 * np.sin(theta), rtol=1e-12, atol=1e-15
    )
    # Gravity is saved in the source record and rebuilt from it.
    rebuilt = sb.Mechanism.from_source(mechanism.source)
    np.testing.assert_array_equal(rebuilt.gravity, [-9.81, 0, 0])


@pytest.mark.parametrize("gravity", [[0.0, -9.81], [0.0, 0.0, np.nan], "down"])
def test_bad_gravity_rejected(gravity):
    """Bad gravity (also as it would come from a config file) is an InputError naming the value."""
    with pytest.raises(sb.InputError, match="gravity"):
        sb.Mechanism.from_urdf(R2, gravity=gravity)


# ---------------------------------------------------------------------- bad files and names
def test_malformed_urdf_file_named(tmp_path):
    broken = tmp_path / "broken_arm.urdf"
    broken.write_text('<?xml version="1.0"?><robot name="x"><link name="a"></robot>')
    with pytest.raises(sb.InputError, match="broken_arm.urdf"):
        sb.Mechanism.from_urdf(broken)


def test_missing_urdf_file_named(tmp_path):
    with pytest.raises(sb.InputError, match="no_such_arm.urdf"):
        sb.Mechanism.from_urdf(tmp_path / "no_such_arm.urdf")


def test_malformed_urdf_string_rejected():
    with pytest.raises(sb.InputError, match="URDF"):
        sb.Mechanism.from_urdf_string("<robot name='x'><joint name='j' type='revolute'>")


def test_unknown_body_named():
    mechanism = sb.Mechanism.from_urdf(R2)
    with pytest.raises(sb.InputError, match="forearm"):
        mechanism.frame_id("forearm")
    workspace = sb.Workspace.grid(mechanism, 5)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("forearm", (0.2, 0, 0)), stiffness=100.0
    )
    with pytest.raises(sb.InputError, match="forearm"):
        sb.DesignProblem(mechanism, workspace, [spring])


def test_unknown_joint_named():
    mechanism = sb.Mechanism.from_urdf(R2)
    with pytest.raises(sb.InputError, match="elbow"):
        mechanism.joint("elbow")
    workspace = sb.Workspace.grid(mechanism, 5)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.2, 0, 0)), stiffness=100.0
    )
    with pytest.raises(sb.InputError, match="elbow"):
        sb.DesignProblem(mechanism, workspace, [spring], weights={"elbow": 1.0})


# ---------------------------------------------------------------------- joint kinds
CONTINUOUS = _robot(
    "continuous_link",
    _link("ground"),
    _link("link1", 1.0, (0.25, 0, 0)),
    _joint("theta", "continuous", "ground", "link1"),
)


def test_continuous_joint_uses_cos_sin_and_balances():
    mechanism = sb.Mechanism.from_urdf_string(CONTINUOUS, gravity=9.8)
    (joint,) = mechanism.joints
    assert joint.kind == "continuous"
    assert (joint.lower, joint.upper) == (-np.pi, np.pi)
    assert mechanism.model.nq == 2 and mechanism.nv == 1
    theta = np.linspace(-np.pi, np.pi, 9)
    q = mechanism.configurations(theta[:, None])
    np.testing.assert_allclose(q, np.column_stack([np.cos(theta), np.sin(theta)]), rtol=0, atol=1e-15)
    workspace = sb.Workspace.grid(mechanism, 361)
    gravity = workspace.kinematics().gravity_torque[:, 0]
    np.testing.assert_allclose(gravity, 9.8 * 0.25 * np.cos(workspace.joint_values[:, 0]), rtol=0, atol=1e-12)
    # The zero-free-length balance of docs/model.md §9 holds on a continuous joint too.
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.2, 0, 0)), stiffness=9.8 * 0.25 / (0.1 * 0.2)
    )
    tau = sb.DesignProblem(mechanism, workspace, [spring]).evaluate(np.zeros(0)).tau
    assert np.max(np.abs(tau)) < 1e-9


def test_continuous_robot_from_example_robot_data():
    mechanism = sb.Mechanism.from_robot("double_pendulum_continuous")
    assert [j.kind for j in mechanism.joints] == ["continuous", "continuous"]
    assert mechanism.model.nq == 4
    workspace = sb.Workspace.random(mechanism, 6, seed=0)
    spring = RefSpring("universe", (0.0, 0.05, 0.3), "link2", (0.0, 0.0, 0.1), 300.0, 0.05, 2.0)
    problem = sb.DesignProblem(
        mechanism,
        workspace,
        [
            sb.ExtensionSpring(
                sb.Anchor(spring.body_a, spring.point_a),
                sb.Anchor(spring.body_b, spring.point_b),
                stiffness=spring.stiffness,
                free_length=spring.free_length,
                initial_tension=spring.initial_tension,
                keep_tension=False,
            )
        ],
    )
    tau = problem.evaluate(np.zeros(0)).tau
    reference = ReferencePotential(mechanism.model, [spring])
    for i, q in enumerate(workspace.configurations):
        expected = reference.torque(q)
        np.testing.assert_allclose(tau[i], expected, rtol=0, atol=1e-6 * max(np.max(np.abs(expected)), 1.0))


SLIDER = _robot(
    "slider",
    _link("base"),
    _link("carriage", 2.5),
    _joint("lift", "prismatic", "base", "carriage", axis=(0, 0, 1), limits=(-0.5, 0.5)),
)


def test_prismatic_vertical_slider():
    mechanism = sb.Mechanism.from_urdf_string(SLIDER)
    (joint,) = mechanism.joints
    assert joint.kind == "prismatic" and joint.unit == "m" and joint.torque_unit == "N"
    assert (joint.lower, joint.upper) == (-0.5, 0.5)
    # degrees=True converts angles only: a prismatic range stays in metres.
    workspace = sb.Workspace.grid(mechanism, 5, ranges={"lift": (-0.2, 0.2)}, degrees=True)
    np.testing.assert_allclose(workspace.joint_values[:, 0], np.linspace(-0.2, 0.2, 5), rtol=0, atol=1e-15)
    # Holding force of a vertical slider: m g upwards, whatever the height.
    np.testing.assert_allclose(workspace.kinematics().gravity_torque[:, 0], 2.5 * 9.81, rtol=1e-12)
    # A zero-free-length spring from 1 m above pulls up with k (1 - z): holding force m g - k (1 - z).
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 1.0)), sb.Anchor("carriage", (0, 0, 0)), stiffness=20.0
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    z = workspace.joint_values[:, 0]
    np.testing.assert_allclose(result.residual_torque()[:, 0], 2.5 * 9.81 - 20.0 * (1.0 - z), rtol=1e-12)
    row = result.metrics()["joints"][0]
    assert row["unit"] == "N"
    assert row["peak_before"] == pytest.approx(2.5 * 9.81, rel=1e-12)


# Two arms on one base (a tree): left shoulder/elbow and right shoulder/elbow.
TREE = _robot(
    "two_branches",
    _link("base"),
    _link("left_upper", 1.5, (0.15, 0, 0)),
    _link("left_lower", 0.8, (0.12, 0, 0)),
    _link("right_upper", 1.2, (0.14, 0, 0)),
    _link("right_lower", 0.6, (0.1, 0.02, 0)),
    _joint("left_shoulder", "revolute", "base", "left_upper", xyz=(0, 0.2, 0.5)),
    _joint("left_elbow", "revolute", "left_upper", "left_lower", xyz=(0.3, 0, 0)),
    _joint("right_shoulder", "revolute", "base", "right_upper", xyz=(0, -0.2, 0.5), axis=(0, -1, 0.3)),
    _joint("right_elbow", "revolute", "right_upper", "right_lower", xyz=(0.28, 0, 0), axis=(0, 0, 1)),
)


def test_tree_shaped_model_in_design_problem():
    mechanism = sb.Mechanism.from_urdf_string(TREE)
    assert mechanism.nv == 4
    workspace = sb.Workspace.random(mechanism, 12, seed=2)
    reference_springs = [
        RefSpring("base", (0.0, 0.2, 0.7), "left_upper", (0.1, 0.0, 0.02), 400.0, 0.08, 3.0),
        RefSpring("left_upper", (0.05, 0.0, 0.05), "left_lower", (0.1, 0.0, 0.0), 250.0, zero_free_length=True),
        RefSpring("universe", (0.0, -0.2, 0.8), "right_lower", (0.15, 0.0, 0.0), 150.0, 0.1, 0.0),
        RefSpring("left_lower", (0.2, 0.0, 0.0), "right_lower", (0.1, 0.0, 0.0), 80.0, 0.2, 5.0),  # across branches
    ]
    springs = [
        sb.ZeroFreeLengthSpring(sb.Anchor(s.body_a, s.point_a), sb.Anchor(s.body_b, s.point_b), stiffness=s.stiffness)
        if s.zero_free_length
        else sb.ExtensionSpring(
            sb.Anchor(s.body_a, s.point_a),
            sb.Anchor(s.body_b, s.point_b),
            stiffness=s.stiffness,
            free_length=s.free_length,
            initial_tension=s.initial_tension,
            keep_tension=False,
        )
        for s in reference_springs
    ]
    problem = sb.DesignProblem(mechanism, workspace, springs)
    evaluation = problem.evaluate(np.zeros(0))
    reference = ReferencePotential(mechanism.model, reference_springs)
    for i, q in enumerate(workspace.configurations):
        expected = reference.torque(q)
        np.testing.assert_allclose(evaluation.tau[i], expected, rtol=0, atol=1e-6 * max(np.max(np.abs(expected)), 1.0))
        assert evaluation.potential[i] == pytest.approx(reference(q), rel=1e-10, abs=1e-10)
    # A free design on the tree solves and reduces the gravity torque of both branches.
    free = [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("base", (0, 0.2, 0.7)),
            sb.Anchor("left_upper", sb.Free([0, 0, 0], [0.3, 0, 0])),
            stiffness=sb.Free(0, 2000),
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("base", (0, -0.2, 0.7)),
            sb.Anchor("right_upper", sb.Free([0, 0, 0], [0.3, 0, 0])),
            stiffness=sb.Free(0, 2000),
        ),
    ]
    result = sb.solve(sb.DesignProblem(mechanism, workspace, free), starts=2)
    rows = {row["joint"]: row for row in result.metrics()["joints"]}
    assert rows["left_shoulder"]["rms_after"] < rows["left_shoulder"]["rms_before"]
    assert rows["right_shoulder"]["rms_after"] < rows["right_shoulder"]["rms_before"]


# A parallelogram-like arm (docs/model.md §1: closed chains as URDF mimic joints): the forearm
# joint mimics the shoulder with multiplier -1, so the forearm keeps its orientation.
MIMIC = _robot(
    "mimic_arm",
    _link("base"),
    _link("upper", 1.0, (0.2, 0, 0)),
    _link("fore", 0.5, (0.1, 0, 0)),
    _joint("shoulder", "revolute", "base", "upper", limits=(-1.2, 1.2)),
    _joint("wrist", "revolute", "upper", "fore", xyz=(0.4, 0, 0), limits=(-1.2, 1.2)).replace(
        "</joint>", '<mimic joint="shoulder" multiplier="-1" offset="0"/></joint>'
    ),
)


def test_mimic_joint_mechanism_evaluates():
    mechanism = sb.Mechanism.from_urdf_string(MIMIC, mimic=True)
    assert mechanism.joint_names == ["shoulder"]
    workspace = sb.Workspace.grid(mechanism, 7)
    s = workspace.joint_values[:, 0]
    # Gravity holding torque: upper arm 1 kg at 0.2 m, forearm 0.5 kg at the elbow (0.4 m)
    # plus 0.1 m along a forearm that stays horizontal: V = g (0.2 + 0.2) sin s.
    np.testing.assert_allclose(workspace.kinematics().gravity_torque[:, 0], 9.81 * 0.4 * np.cos(s), rtol=1e-12)
    spring = RefSpring("universe", (0.0, 0.0, 0.1), "fore", (0.1, 0.0, 0.0), 50.0, zero_free_length=True)
    problem = sb.DesignProblem(
        mechanism,
        workspace,
        [
            sb.ZeroFreeLengthSpring(
                sb.Anchor(spring.body_a, spring.point_a),
                sb.Anchor(spring.body_b, spring.point_b),
                stiffness=spring.stiffness,
            )
        ],
    )
    evaluation = problem.evaluate(np.zeros(0))
    reference = ReferencePotential(mechanism.model, [spring])
    for i, q in enumerate(workspace.configurations):
        expected = reference.torque(q)
        np.testing.assert_allclose(evaluation.tau[i], expected, rtol=0, atol=1e-6 * max(np.max(np.abs(expected)), 1.0))
        assert evaluation.potential[i] == pytest.approx(reference(q), rel=1e-10, abs=1e-10)


def test_mimic_joints_loaded_without_mimic_warn():
    urdf = Path(__file__).resolve().parents[2] / "urdf" / "parallelogram_arm.urdf"
    with pytest.warns(UserWarning, match="declares mimic joints"):
        independent = sb.Mechanism.from_urdf(urdf)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coupled = sb.Mechanism.from_urdf(urdf, mimic=True)
    assert independent.nv > coupled.nv  # without mimic the follower joints become degrees of freedom
