"""Closed chains written as URDF trees with mimic joints (Pinocchio ``mimic=True``).

urdf/parallelogram_arm.urdf: a parallelogram-driven two-link arm. Independent joints
shoulder (theta1, upper arm from horizontal) and elbow (theta2 - theta1); the coupler and
the crank of the parallelogram are mimic joints. Hand-derived (comment of the URDF):

    V = g [(m1 r1 + m2 l1 + m3 l1/2) sin theta1 + (m2 r2 - m3 b - m4 b/2) sin theta2],
    tau_shoulder = C1 + C2,  tau_elbow = C2,  C_i = dV/dtheta_i,

with m1 = 3 kg, r1 = 0.3 m, l1 = 0.6 m, m2 = 2 kg, r2 = 0.25 m, coupler m3 = 0.5 kg, crank
m4 = 0.3 kg, lever b = 0.1 m, g = 9.81.

urdf/sit_to_stand_four_bar.urdf: a seat on a parallelogram four-bar, one actuated joint
``lift``: ``tau = g (m_rear L/2 + m_front L/2 + m_seat L) cos(lift)`` with arms 1.5 kg each,
L = 0.45 m, seat 8 kg; one zero-free-length spring with ``k a b = g (that moment)``
balances it exactly (docs/model.md §9).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf"
G = 9.81
M1, R1, L1, M2, R2, M3, M4, B = 3.0, 0.3, 0.6, 2.0, 0.25, 0.5, 0.3, 0.1
SEAT_MOMENT = 1.5 * 0.225 * 2 + 8.0 * 0.45  # [kg·m]


@pytest.fixture(scope="module")
def arm():
    mechanism = sb.Mechanism.from_urdf(URDF / "parallelogram_arm.urdf", mimic=True)
    workspace = sb.Workspace.random(
        mechanism, 50, ranges={"shoulder": [-180, 180], "elbow": [-180, 180]}, degrees=True, seed=7
    )
    return mechanism, workspace


def test_parallelogram_samples_only_independent_joints(arm):
    mechanism, workspace = arm
    assert mechanism.joint_names == ["shoulder", "elbow"]
    assert workspace.joint_values.shape == (50, 2)
    assert workspace.kinematics().gravity_torque.shape == (50, 2)
    with pytest.raises(sb.InputError, match="coupler_joint"):
        sb.Workspace.grid(mechanism, 4, ranges={"coupler_joint": [0, 1]})
    # without mimic=True the URDF's mimic joints would be free joints of their own
    with pytest.warns(UserWarning, match="declares mimic joints"):
        assert sb.Mechanism.from_urdf(URDF / "parallelogram_arm.urdf").nv == 4


def test_parallelogram_loop_closes(arm):
    mechanism, workspace = arm
    model, data = mechanism.model, mechanism.model.createData()
    for q in workspace.configurations:
        pin.framesForwardKinematics(model, data, q)
        # the crank's far end lands on the shoulder pivot O, and the coupler stays parallel to the upper arm
        np.testing.assert_allclose(data.oMf[mechanism.frame_id("crank")].act(np.array([B, 0.0, 0.0])), 0.0, atol=1e-12)
        np.testing.assert_allclose(
            data.oMf[mechanism.frame_id("coupler")].rotation,
            data.oMf[mechanism.frame_id("upper_arm")].rotation,
            atol=1e-12,
        )


def test_parallelogram_gravity_torque_matches_hand_formula(arm):
    _, workspace = arm
    theta1 = workspace.joint_values[:, 0]
    theta2 = theta1 + workspace.joint_values[:, 1]
    c1 = G * (M1 * R1 + M2 * L1 + M3 * L1 / 2) * np.cos(theta1)  # [N·m]
    c2 = G * (M2 * R2 - M3 * B - M4 * B / 2) * np.cos(theta2)  # [N·m]
    torque = workspace.kinematics().gravity_torque
    np.testing.assert_allclose(torque[:, 0], c1 + c2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(torque[:, 1], c2, rtol=0, atol=1e-9)


def test_parallelogram_spring_torques_on_actuated_joints(arm):
    # A zero-free-length spring from the ground to the coupler (a mimic body): its torque
    # on the actuated joints is dV/dq of V = k |x_b - x_a|^2 / 2, checked by finite differences.
    mechanism, workspace = arm
    k, ground_point, coupler_point = 120.0, np.array([0.0, 0.0, 0.2]), np.array([-0.3, 0.0, 0.0])
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", ground_point), sb.Anchor("coupler", coupler_point), stiffness=k
    )
    evaluation = sb.DesignProblem(mechanism, workspace, [spring]).evaluate(np.zeros(0))
    model, data = mechanism.model, mechanism.model.createData()
    frame = mechanism.frame_id("coupler")

    def spring_potential(joint_values):
        pin.framesForwardKinematics(model, data, mechanism.configurations(joint_values[None])[0])
        return 0.5 * k * float(np.sum((data.oMf[frame].act(coupler_point) - ground_point) ** 2))

    gravity = workspace.kinematics().gravity_torque
    for i, values in enumerate(workspace.joint_values[:10]):
        step = 1e-6
        derivative = [
            (spring_potential(values + step * e) - spring_potential(values - step * e)) / (2 * step) for e in np.eye(2)
        ]
        np.testing.assert_allclose(evaluation.tau[i] - gravity[i], derivative, atol=1e-6)


def test_sit_to_stand_balances_exactly_with_one_spring(tmp_path):
    mechanism = sb.Mechanism.from_urdf(URDF / "sit_to_stand_four_bar.urdf", mimic=True)
    assert mechanism.joint_names == ["lift"]
    workspace = sb.Workspace.random(mechanism, 50, seed=3)
    lift = workspace.joint_values[:, 0]
    assert np.all((lift >= -np.pi / 6) & (lift <= np.pi / 3))
    np.testing.assert_allclose(
        workspace.kinematics().gravity_torque[:, 0], G * SEAT_MOMENT * np.cos(lift), rtol=0, atol=1e-9
    )
    a, b = 0.15, 0.3
    k = G * SEAT_MOMENT / (a * b)  # k a b = m g c  [N/m]
    spring = sb.ZeroFreeLengthSpring(sb.Anchor("ground", (0, 0, a)), sb.Anchor("rear_arm", (b, 0, 0)), stiffness=k)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    assert result.exact_balance()["exact"]
    assert "Exactly balanced" in result.table()
    loaded = sb.DesignResult.load(result.save(tmp_path / "seat.json"))
    assert loaded.problem.mechanism.joint_names == ["lift"]
    np.testing.assert_allclose(loaded.residual_torque(), result.residual_torque(), atol=1e-12)
