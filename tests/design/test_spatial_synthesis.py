"""Spatial exact balance by construction and the proofs that a topology cannot reach it.

The synthesised designs are checked independently of the code: the holding torque is the central
difference of the total potential computed from Pinocchio alone (physics_helpers.ReferencePotential:
``computePotentialEnergy`` plus ``k L²/2`` per spring), at random poses, against Pinocchio's gravity torque.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from physics_helpers import ReferencePotential, RefSpring
from spatial_helpers import G, yaw_pitch_roll
from springbalance import exact


def _worst_torque_ratio(mechanism: sb.Mechanism, springs: list, poses: int = 12, seed: int = 4) -> float:
    """Largest |τ| over random poses, relative to the largest gravity torque there (finite differences)."""
    model = mechanism.model
    reference = ReferencePotential(
        model,
        [
            RefSpring(
                s.anchors["a"].body,
                tuple(s.anchors["a"].point),
                s.anchors["b"].body,
                tuple(s.anchors["b"].point),
                float(s.parameters["stiffness"]),
                zero_free_length=True,
            )
            for s in springs
        ],
    )
    rng = np.random.default_rng(seed)
    data = model.createData()
    worst, scale, h = 0.0, 0.0, 1e-5

    def potential(angles: np.ndarray) -> float:  # continuous joints store (cos, sin)
        return reference(mechanism.configurations(angles)[0])

    for _ in range(poses):
        angles = rng.uniform(-np.pi, np.pi, mechanism.nv)
        tau = [(potential(angles + h * e) - potential(angles - h * e)) / (2 * h) for e in np.eye(mechanism.nv)]
        worst = max(worst, float(np.max(np.abs(tau))))
        q = mechanism.configurations(angles)[0]
        scale = max(scale, float(np.max(np.abs(pin.computeGeneralizedGravity(model, data, q)))))
    return worst / scale


def _offset_ur5() -> sb.Mechanism:
    """The UR5 with every link's centre of mass moved by up to 5 cm in each direction."""
    model = sb.Mechanism.from_robot("ur5").model.copy()
    rng = np.random.default_rng(7)
    for j in range(1, model.njoints):
        inertia = model.inertias[j]
        model.inertias[j] = pin.Inertia(inertia.mass, inertia.lever + rng.uniform(-0.05, 0.05, 3), inertia.inertia)
    return sb.Mechanism.from_model(model)


def test_the_ur5_is_balanced_by_construction():
    ur5 = sb.Mechanism.from_robot("ur5")
    synthesis = exact.synthesize_spatial(ur5)
    assert synthesis.exact and synthesis.coefficients.relative < 1e-12
    assert len(synthesis.springs) == sum(synthesis.pairs.values()) and max(synthesis.pairs.values()) <= 2
    assert _worst_torque_ratio(ur5, synthesis.springs) < 1e-7  # finite differences: round-off ~1e-9


def test_a_ur5_with_offset_centres_of_mass_is_balanced_by_construction():
    arm = _offset_ur5()
    synthesis = exact.synthesize_spatial(arm, stiffness=800.0)
    assert synthesis.exact
    assert all(float(s.parameters["stiffness"]) == 800.0 for s in synthesis.springs)
    assert _worst_torque_ratio(arm, synthesis.springs) < 1e-7


def test_the_yaw_pitch_roll_arm_needs_one_spring():
    arm = yaw_pitch_roll()
    synthesis = exact.synthesize_spatial(arm)
    assert len(synthesis.springs) == 1 and synthesis.exact
    assert _worst_torque_ratio(arm, synthesis.springs) < 1e-7


_LINK = (
    '<link name="{0}"><inertial><origin xyz="{1}"/><mass value="{2}"/>'
    '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'
)
_JOINT = (
    '<joint name="{0}" type="{5}"><parent link="{1}"/><child link="{2}"/><origin xyz="{3}" rpy="0.3 -0.2 0.5"/>'
    '<axis xyz="{4}"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
)


def test_a_tree_with_skew_axes_and_a_continuous_joint_is_balanced_by_construction():
    # a torso on a continuous waist carrying two arms, every joint placement turned (rpy) and axes skew
    links = [("torso", "0.02 0 0.3", 5), ("arm_l", "0.2 0.03 0", 2), ("fore_l", "0.15 0 0.01", 1)]
    links += [("arm_r", "0.2 -0.02 0", 2), ("hand_r", "0.05 0.01 0", 0.5)]
    joints = [
        ("waist", "ground", "torso", "0 0 0.1", "0 0 1", "continuous"),
        ("sh_l", "torso", "arm_l", "0 0.2 0.5", "0 1 0", "revolute"),
        ("el_l", "arm_l", "fore_l", "0.3 0 0", "0 0.6 0.8", "revolute"),
        ("sh_r", "torso", "arm_r", "0 -0.2 0.5", "1 1 0", "revolute"),
        ("wr_r", "arm_r", "hand_r", "0.3 0 0", "1 0 0", "revolute"),
    ]
    text = (
        '<?xml version="1.0"?><robot name="tree"><link name="ground"/>'
        + "".join(_LINK.format(*link) for link in links)
        + "".join(_JOINT.format(*joint) for joint in joints)
        + "</robot>"
    )
    tree = sb.Mechanism.from_urdf_string(text, gravity=G)
    synthesis = exact.synthesize_spatial(tree)
    assert synthesis.exact
    # gravity couples no body of one arm to one of the other: no spring joins the two arms
    left, right = {"arm_l", "fore_l"}, {"arm_r", "hand_r"}
    assert not any({a, b} & left and {a, b} & right for a, b in synthesis.pairs)
    assert _worst_torque_ratio(tree, synthesis.springs) < 1e-7


def test_a_pair_the_topology_lacks_is_named():
    synthesis = exact.synthesize_spatial(yaw_pitch_roll(), allowed=[("link2", "link3")])
    assert not synthesis.exact and synthesis.missing == [("link1", "link2")]
    assert "link1–link2" in synthesis.describe()


def test_a_spring_that_misses_the_pitch_cannot_balance():
    arm = yaw_pitch_roll()
    # a spring between link 2 and link 3 depends on the roll only; gravity's sin θ₂ term is out of its reach
    verdict = exact.spatial_reachability(arm, [("link2", "link3")])
    assert verdict.unreachable and "pitch" in verdict.reason
    assert not exact.spatial_reachability(arm, [("ground", "link2")]).unreachable  # the hand-derived spring


def test_the_ur5_wrist_needs_a_spring_across_wrist_1():
    ur5 = sb.Mechanism.from_robot("ur5")
    # wrist 3 (0.1879 kg) sits 0.09465 m out along wrist 2's axis, which wrist 1 turns: gravity has the
    # coefficient g·0.1879·0.09465 on (lift, elbow, wrist 1), and a shoulder→forearm spring misses wrist 1
    terms = exact.spatial_coefficients(ur5, []).terms()
    assert abs(terms["sin shoulder_lift_joint · sin elbow_joint · cos wrist_1_joint"]) == pytest.approx(
        G * 0.1879 * 0.09465, rel=1e-9
    )
    test = exact.SpatialReachability(ur5)
    verdict = test.verdict([("shoulder_link", "forearm_link"), ("upper_arm_link", "forearm_link")])
    assert verdict.unreachable and "wrist_1_joint" in verdict.reason
    assert not test.verdict([("shoulder_link", "wrist_1_link")]).unreachable


def test_three_ground_springs_with_anchors_in_boxes_balance_the_ur5():
    # the topology explore's fewest-springs search finds on the UR5: the ground to the forearm, wrist 1 and
    # wrist 2, every anchor free in a ±0.3 m box of its link's frame; checked by Pinocchio's potential alone
    ur5 = sb.Mechanism.from_robot("ur5")
    box = ((-0.3, -0.3, -0.3), (0.3, 0.3, 0.3))
    links = ("forearm_link", "wrist_1_link", "wrist_2_link")
    ends = [exact.SpringEnds("universe", box, link, box) for link in links]
    fit, springs = exact.synthesize_in_boxes(ur5, ends, stiffness=(0.0, 5000.0), names=list(links))
    assert fit.relative < exact.SPATIAL_EXACT
    assert [s.name for s in springs] == list(links)
    for spring in springs:
        for end in ("a", "b"):
            assert np.all(np.abs(spring.anchors[end].point) <= 0.3 + 1e-12)
        assert 0.0 <= float(spring.parameters["stiffness"]) <= 5000.0
    assert _worst_torque_ratio(ur5, springs) < 1e-7
