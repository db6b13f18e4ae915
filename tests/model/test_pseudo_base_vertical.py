"""Pseudo-bases that keep only the vertical (``keep: vertical``, issue 29): on the KR-like arm, whose first joint a1
turns about the world's vertical, the undo chains skip a1, so the bodies turn with a1 about ``ẑ`` and keep ``ẑ``.

Expected values from the physics, not from the code: the body's orientation is ``Rz(q₁)`` (a1's axis is +z with
no origin rotation), its origin the joint's; a spring anchored at ``a = l_a ẑ`` on it sees ``R_pb a = l_a ẑ`` whatever
``q₁``, so the seed's design (tests/model/test_pseudo_bases.py) balances exactly as with world-oriented
pseudo-bases. The residual is computed with Pinocchio alone: ``g(q)`` (``computeGeneralizedGravity``) plus, per
spring, ``k (J_a − J_b)ᵀ (x_a − x_b)`` from the frames' placements and Jacobians.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from test_pseudo_bases import PB_MASS, G, _hand_springs, _lumped_moments, _poses

import springbalance as sb
from springbalance.design.problem import DesignProblem
from springbalance.errors import InputError
from springbalance.results.result import DesignResult

ROOT = Path(__file__).resolve().parents[2]
KR = ROOT / "urdf" / "kr_like_6r.urdf"
JOINTS = ["a2", "a3", "a4", "a5", "a6"]
KEEP = ("orientation", "vertical")


def _bases(keep):
    return [{"joint": joint, "mass": PB_MASS.get(joint, 0.0), "keep": keep} for joint in JOINTS]


@pytest.fixture(scope="module")
def vertical():
    return sb.Mechanism.from_urdf(KR, pseudo_bases=_bases("vertical"))


def _rz(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_vertical_pseudo_base_turns_with_the_vertical_joint_only(vertical):
    data = vertical.model.createData()
    poses = _poses(vertical, 40, seed=21)
    for pose, q in zip(poses, vertical.configurations(poses)):
        pin.framesForwardKinematics(vertical.model, data, q)
        for joint in JOINTS:
            placement = data.oMf[vertical.frame_id(f"pb_{joint}")]
            np.testing.assert_allclose(placement.rotation[:, 2], [0.0, 0.0, 1.0], rtol=0, atol=1e-12)
            np.testing.assert_allclose(placement.rotation, _rz(pose[0]), rtol=0, atol=1e-12)
            origin = data.oMi[vertical.model.getJointId(joint)].translation
            np.testing.assert_allclose(placement.translation, origin, rtol=0, atol=1e-12)


def test_vertical_pseudo_bases_use_fewer_mimic_joints(vertical):
    """pb_a_k undoes the k−1 joints before it when keeping the orientation, k−2 (all but a1) keeping the vertical."""
    full = sb.Mechanism.from_urdf(KR, pseudo_bases=_bases("orientation"))

    def undo(mechanism):
        return sum("__undo_" in name for name in mechanism.model.names)

    assert undo(full) == 1 + 2 + 3 + 4 + 5
    assert undo(vertical) == 0 + 1 + 2 + 3 + 4
    assert not any("__undo_a1" in name for name in vertical.model.names)


def _holding(mechanism, springs, q):
    """``∂(V_g + V_s)/∂q`` [N·m] with Pinocchio: gravity, and each zero-free-length spring's
    ``k (J_a − J_b)ᵀ (x_a − x_b)`` (``J`` the anchor point's world-aligned translational Jacobian)."""
    model = mechanism.model
    data = model.createData()
    tau = pin.computeGeneralizedGravity(model, data, q).copy()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    for spring in springs:
        ends = []
        for end in ("a", "b"):
            anchor = spring.anchors[end]
            frame = mechanism.frame_id(anchor.body)
            placement = data.oMf[frame]
            offset = placement.rotation @ np.asarray(anchor.region().point([]), dtype=float)
            jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
            ends.append((placement.translation + offset, jacobian[:3] - pin.skew(offset) @ jacobian[3:]))
        (xa, ja), (xb, jb) = ends
        tau += spring.parameters["stiffness"] * (ja - jb).T @ (xa - xb)
    return tau


def test_springs_on_vertical_pseudo_bases_balance_the_kr_arm_exactly(vertical):
    springs = _hand_springs(_lumped_moments(KR, PB_MASS), JOINTS)
    poses = _poses(vertical, 100, seed=4)
    configurations = vertical.configurations(poses)
    data = vertical.model.createData()
    unbalanced = max(np.max(np.abs(pin.computeGeneralizedGravity(vertical.model, data, q))) for q in configurations)
    assert unbalanced > 50  # tens of N·m on a2
    residual = np.array([_holding(vertical, springs, q) for q in configurations])
    assert np.max(np.abs(residual)) <= 1e-9 * unbalanced
    # an anchor off the body's z axis turns with a1 and breaks the balance: the vertical is all it keeps
    tilted = _hand_springs(_lumped_moments(KR, PB_MASS), JOINTS)
    tilted[0] = sb.ZeroFreeLengthSpring(
        sb.Anchor("pb_a2", [0.05, 0.0, 0.15]),
        springs[0].anchors["b"],
        "tilted",
        stiffness=springs[0].parameters["stiffness"],
    )
    residual = np.array([_holding(vertical, tilted, q) for q in configurations])
    assert np.max(np.abs(residual)) > 1e-3 * unbalanced


def test_vertical_pseudo_base_weighs_as_a_world_oriented_one():
    """Gravity sees only the height of the centre of mass, and ``Rz(ψ) c`` has the height of ``c``."""
    bases = [{"joint": "a4", "mass": 0.7, "com": [0.02, -0.01, 0.05], "keep": keep} for keep in KEEP]
    poses = _poses(sb.Mechanism.from_urdf(KR), 20, seed=6)
    torques = [
        sb.Workspace.from_array(sb.Mechanism.from_urdf(KR, pseudo_bases=[base]), poses).kinematics().gravity_torque
        for base in bases
    ]
    np.testing.assert_allclose(torques[0], torques[1], rtol=0, atol=1e-12 * G)


def test_bad_keep_is_named():
    with pytest.raises(InputError) as error:
        sb.Mechanism.from_urdf(KR, pseudo_bases=[{"joint": "a2", "keep": "upright"}])
    assert str(error.value) == "pseudo_bases[0].keep: expected 'orientation' or 'vertical', got 'upright'"


def test_ur5_vertical_pseudo_base_skips_the_shoulder_pan():
    """The UR5's shoulder pan turns about the vertical; its elbow's pseudo-base then undoes only the shoulder lift
    (and keeps ẑ), while its origin rotations (±π/2 about several axes) are still undone."""
    ur5 = sb.Mechanism.from_robot("ur5", pseudo_bases=[{"joint": "wrist_2_joint", "keep": "vertical"}])
    undone = [name for name in ur5.model.names if "__undo_" in name]
    assert undone == [f"pb_wrist_2_joint__undo_{j}" for j in ("wrist_1_joint", "elbow_joint", "shoulder_lift_joint")]
    data = ur5.model.createData()
    poses = _poses(ur5, 20, seed=9)
    for q in ur5.configurations(poses):
        pin.framesForwardKinematics(ur5.model, data, q)
        np.testing.assert_allclose(data.oMf[ur5.frame_id("pb_wrist_2_joint")].rotation[:, 2], [0, 0, 1], atol=1e-12)


def test_report_says_which_pseudo_bases_keep_only_the_vertical():
    mechanism = sb.Mechanism.from_urdf(KR, pseudo_bases=["a2", {"joint": "a3", "keep": "vertical"}])
    poses = _poses(mechanism, 5, seed=1)
    springs = _hand_springs(_lumped_moments(KR, {}), ["a3"])
    result = DesignResult(DesignProblem(mechanism, sb.Workspace.from_array(mechanism, poses), springs), np.zeros(0))
    lines = [line for line in result.table().splitlines() if line.strip().startswith("pb_")]
    assert lines[0].endswith(") m") and lines[1].endswith(") m, keeps only the vertical")
    assert result.to_dict()["pseudo_bases"]["bases"][1]["keep"] == "vertical"
