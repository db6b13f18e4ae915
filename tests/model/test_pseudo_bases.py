"""Pseudo-bases (issue 29, part 2): bodies at a joint's origin that keep the world's orientation.

The expected numbers are worked out here from the arm's URDF, by hand, not by the code under test:
with every link's distal masses lumped at its next joint, gravity's potential is
``V_g = 9.81 Σ_k ẑᵀ R_k s_k`` (``s_k = m_k c_k + M_{>k} d_k`` [kg·m] in link k's frame, ``d_k`` the origin of
joint k+1 in it, ``M_{>k}`` every mass beyond joint k, pseudo-bases included), and a zero-free-length spring
from the pseudo-base at joint k (anchor ``a`` [m], world-aligned) to link k (anchor ``b``) adds
``-k aᵀ R_k b``; so ``a = l_a ẑ``, ``b = l_b s_k/|s_k|``, ``k l_a l_b = g |s_k|`` balances link k exactly
(seed 004 ch. 4: ``k_i l_CA l_CB = μ_i g |σ_i|``).
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from springbalance.design.problem import DesignProblem
from springbalance.errors import InputError
from springbalance.results.result import DesignResult

ROOT = Path(__file__).resolve().parents[2]
KR = ROOT / "urdf" / "kr_like_6r.urdf"
TWO_LINK = ROOT / "urdf" / "two_link_planar.urdf"
G = 9.81
#: the pseudo-bases of the KR-like arm: joints 2..6, one with a mass and a centre of mass off its origin
BASES = ["a2", "a3", {"joint": "a4", "mass": 0.7, "com": [0.02, -0.01, 0.05]}, "a5", {"joint": "a6", "mass": 0.3}]
PB_MASS = {"a4": 0.7, "a6": 0.3}


def _urdf_numbers(path):
    """Per moving link of a serial URDF, read with ElementTree: (mass [kg], com [m], origin of its joint [m])."""
    root = ElementTree.parse(path).getroot()
    links = {}
    for link in root.findall("link"):
        inertial = link.find("inertial")
        links[link.get("name")] = (
            float(inertial.find("mass").get("value")),
            np.array([float(v) for v in inertial.find("origin").get("xyz").split()]),
        )
    joints = [(j.get("name"), j.find("child").get("link"), j.find("origin").get("xyz")) for j in root.findall("joint")]
    return [(name, *links[child], np.array([float(v) for v in xyz.split()])) for name, child, xyz in joints]


def _lumped_moments(path, pb_mass):
    """s_k [kg·m] in link k's frame per joint k (see the module docstring); pb_mass: joint → pseudo-base mass."""
    chain = _urdf_numbers(path)
    moments = {}
    for k, (name, mass, com, _) in enumerate(chain):
        beyond = sum(m for _, m, _, _ in chain[k + 1 :]) + sum(pb_mass.get(j, 0.0) for j, *_ in chain[k + 1 :])
        offset = chain[k + 1][3] if k + 1 < len(chain) else np.zeros(3)
        moments[name] = mass * com + beyond * offset
    return moments


def _hand_springs(moments, joints, la=0.15, lb=0.1):
    springs = []
    for joint in joints:
        s = moments[joint]
        link = "link" + joint[1:]
        springs.append(
            sb.ZeroFreeLengthSpring(
                sb.Anchor(f"pb_{joint}", [0.0, 0.0, la]),
                sb.Anchor(link, lb * s / np.linalg.norm(s)),
                f"s_{joint}",
                stiffness=G * np.linalg.norm(s) / (la * lb),
            )
        )
    return springs


def _fixed(mechanism, springs, poses):
    workspace = sb.Workspace.from_array(mechanism, poses, ordered=False)
    return DesignResult(DesignProblem(mechanism, workspace, springs), np.zeros(0))


@pytest.fixture(scope="module")
def kr():
    return sb.Mechanism.from_urdf(KR, pseudo_bases=BASES)


def _poses(mechanism, n=60, seed=3):
    rng = np.random.default_rng(seed)
    lower = np.array([j.lower for j in mechanism.joints])
    upper = np.array([j.upper for j in mechanism.joints])
    return lower + (upper - lower) * rng.random((n, mechanism.nv))


def test_pseudo_base_keeps_the_world_orientation_at_the_joint_origin(kr):
    data = kr.model.createData()
    for row in kr.configurations(_poses(kr)):
        pin.framesForwardKinematics(kr.model, data, row)
        for joint in ("a2", "a3", "a4", "a5", "a6"):
            placement = data.oMf[kr.frame_id(f"pb_{joint}")]
            np.testing.assert_allclose(placement.rotation, np.eye(3), rtol=0, atol=1e-12)
            origin = data.oMi[kr.model.getJointId(joint)].translation
            np.testing.assert_allclose(placement.translation, origin, rtol=0, atol=1e-12)
    assert kr.joint_names == ["a1", "a2", "a3", "a4", "a5", "a6"]  # the chains add no degree of freedom


def test_pseudo_base_mass_adds_its_weight_at_the_joint_origin(kr):
    """The extra gravity torque is that of a point mass at the joint origin (world-aligned com offsets weigh
    the same at every pose): τ = -m Jᵀ g with J the origin's Jacobian of the bare arm."""
    bare = sb.Mechanism.from_urdf(KR)
    poses = _poses(kr, 20)
    extra = sb.Workspace.from_array(kr, poses).kinematics().gravity_torque
    extra = extra - sb.Workspace.from_array(bare, poses).kinematics().gravity_torque
    data = bare.model.createData()
    expected = []
    for q in bare.configurations(poses):
        pin.computeJointJacobians(bare.model, data, q)
        tau = np.zeros(bare.nv)
        for joint, mass in PB_MASS.items():
            jacobian = pin.getJointJacobian(bare.model, data, bare.model.getJointId(joint), pin.LOCAL_WORLD_ALIGNED)
            tau -= mass * jacobian[:3].T @ np.array([0, 0, -G])
        expected.append(tau)
    np.testing.assert_allclose(extra, np.array(expected), rtol=0, atol=1e-12)


def test_hand_designed_springs_balance_the_kr_arm_exactly(kr):
    """One spring per link pb_k → link_k from the seed's formula: the residual is round-off."""
    moments = _lumped_moments(KR, PB_MASS)
    poses = _poses(kr, 200)
    result = _fixed(kr, _hand_springs(moments, ["a2", "a3", "a4", "a5", "a6"]), poses)
    unbalanced = np.max(np.abs(result.problem.workspace.kinematics().gravity_torque))
    assert unbalanced > 50  # the arm weighs: tens of N·m on a2
    assert np.max(np.abs(result.residual_torque(poses))) <= 1e-12 * unbalanced


def test_seed_formula_for_one_link_on_a_two_link_arm():
    """Two-link planar arm (urdf/two_link_planar.urdf: link1 0.5 m, 2 kg, centre of mass at 0.25 m; link2 1 kg
    at 0.2 m plus a 0.5 kg tool at 0.4 m), pseudo-base of 0.25 kg at the elbow. Link 2's first moment is
    μ₂|σ₂| = 1·0.2 + 0.5·0.4 = 0.4 kg·m along it, so k l_CA l_CB = 0.4 g holds link 2 at every pose; the
    shoulder then carries link 1 and everything beyond lumped at the elbow: (2·0.25 + 1.75·0.5) g cos θ₁."""
    mechanism = sb.Mechanism.from_urdf(TWO_LINK, pseudo_bases=[{"joint": "elbow", "mass": 0.25}])
    la, lb = 0.2, 0.1
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("pb_elbow", [0, 0, la]), sb.Anchor("link2", [lb, 0, 0]), "s", stiffness=0.4 * G / (la * lb)
    )
    poses = np.column_stack([np.linspace(-1.2, 1.2, 25), np.linspace(2.0, -2.0, 25)])
    residual = _fixed(mechanism, [spring], poses).residual_torque(poses)
    assert np.max(np.abs(residual[:, 1])) <= 1e-12 * 0.4 * G
    expected = (2 * 0.25 + 1.75 * 0.5) * G * np.cos(poses[:, 0])
    np.testing.assert_allclose(np.abs(residual[:, 0]), np.abs(expected), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(
    ("bases", "message"),
    [
        (["nope"], "pseudo_bases[0].joint: unknown joint 'nope'"),
        (["a2", "a2"], "pseudo_bases[1].joint: joint 'a2' has a pseudo-base already"),
        ([{"joint": "a2", "mass": -1}], "pseudo_bases[0].mass: expected a finite mass ≥ 0 [kg], got -1"),
        ([{"joint": "a2", "com": [0, 1]}], "pseudo_bases[0].com: expected three finite numbers [m], got [0, 1]"),
        ([{"joint": "a2", "weight": 1}], "pseudo_bases[0]: unknown key 'weight'"),
    ],
)
def test_bad_pseudo_bases_are_named(bases, message):
    with pytest.raises(InputError) as error:
        sb.Mechanism.from_urdf(KR, pseudo_bases=bases)
    assert message in str(error.value) and "\n" not in str(error.value)


def test_prismatic_joint_in_the_chain_and_name_clash_are_refused():
    text = KR.read_text()
    prismatic = text.replace('<joint name="a2" type="revolute">', '<joint name="a2" type="prismatic">')
    with pytest.raises(InputError, match=r"pseudo_bases\[0\]\.joint: 'a3' lies beyond the prismatic joint 'a2'"):
        sb.Mechanism.from_urdf_string(prismatic, pseudo_bases=["a3"])
    clash = text.replace('<link name="link6">', '<link name="pb_a3">').replace('link="link6"', 'link="pb_a3"')
    with pytest.raises(InputError, match=r"pseudo_bases\[0\]\.joint: .*name 'pb_a3', which is taken"):
        sb.Mechanism.from_urdf_string(clash, pseudo_bases=["a3"])


def test_source_rebuilds_the_pseudo_bases(kr):
    again = sb.Mechanism.from_source(kr.source)
    assert [base.to_dict() for base in again.pseudo_bases] == [base.to_dict() for base in kr.pseudo_bases]
    assert again.body_names == kr.body_names
    assert kr.pseudo_bases[2].mass == 0.7 and kr.pseudo_bases[2].com == (0.02, -0.01, 0.05)


def test_report_gives_the_pseudo_bases_mass_and_the_torque_it_adds(kr):
    """design.json's peak per joint is the peak of -Σ m Jᵀγ over the samples (J: the bare arm's Jacobian of the
    joint origins); the text report names each pseudo-base and the total mass."""
    poses = _poses(kr, 30, seed=8)
    result = _fixed(kr, _hand_springs(_lumped_moments(KR, PB_MASS), ["a2"]), poses)
    bare = sb.Mechanism.from_urdf(KR)
    data = bare.model.createData()
    torques = []
    for q in bare.configurations(poses):
        pin.computeJointJacobians(bare.model, data, q)
        tau = np.zeros(bare.nv)
        for joint, mass in PB_MASS.items():
            jacobian = pin.getJointJacobian(bare.model, data, bare.model.getJointId(joint), pin.LOCAL_WORLD_ALIGNED)
            tau += mass * G * jacobian[2]  # -m Jᵀ γ with γ = (0, 0, -g)
        torques.append(tau)
    record = result.to_dict()["pseudo_bases"]
    assert record["total_mass"] == pytest.approx(1.0, abs=1e-15)
    peaks = np.max(np.abs(np.array(torques)), axis=0)
    np.testing.assert_allclose(list(record["peak_torque"].values()), peaks, rtol=1e-12, atol=1e-12)
    assert peaks[1] > 1 and record["peak_torque"]["a6"] == 0.0  # nothing beyond a6's origin hangs on a6
    assert [base["body"] for base in record["bases"]] == ["pb_a2", "pb_a3", "pb_a4", "pb_a5", "pb_a6"]
    text = result.table()
    assert "Pseudo-bases (world-oriented anchors, docs/model.md §1.1): 1 kg in all" in text
    assert "pb_a4            at joint a4: 0.7 kg, centre of mass (0.02, -0.01, 0.05) m" in text


@pytest.mark.parametrize(
    "make",
    [
        lambda: sb.Mechanism.from_robot("ur5", pseudo_bases=["elbow_joint", "wrist_2_joint", "wrist_3_joint"]),
        lambda: sb.Mechanism.from_urdf_string(
            KR.read_text().replace('<joint name="a1" type="revolute">', '<joint name="a1" type="continuous">'),
            pseudo_bases=["a3", "a6"],
        ),
    ],
    ids=["ur5_origin_rotations", "continuous_joint_in_the_chain"],
)
def test_orientation_is_kept_on_other_arms(make):
    """The UR5's joint origins turn by ±π/2 about several axes; a continuous joint is mimicked as well."""
    mechanism = make()
    data = mechanism.model.createData()
    for row in mechanism.configurations(_poses(mechanism, 40, seed=11)):
        pin.framesForwardKinematics(mechanism.model, data, row)
        for base in mechanism.pseudo_bases:
            np.testing.assert_allclose(data.oMf[mechanism.frame_id(base.body)].rotation, np.eye(3), atol=1e-12)
