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
    for _ in range(poses):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        tau = [(reference(q + h * e) - reference(q - h * e)) / (2 * h) for e in np.eye(model.nq)]
        worst = max(worst, float(np.max(np.abs(tau))))
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
