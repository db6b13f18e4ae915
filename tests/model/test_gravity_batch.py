"""Gravity torque and potential of a workspace, batched: the per-sample, per-joint loop's numbers."""

import warnings

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from springbalance.model.kinematics import gravity_and_potential


def _loop(model, configurations):
    """The reference: Pinocchio's gravity and the potential summed body by body, sample by sample."""
    data = model.createData()
    gravity = np.array(model.gravity.linear)
    torques, potentials = [], []
    for q in configurations:
        torques.append(np.array(pin.computeGeneralizedGravity(model, data, q)))
        pin.forwardKinematics(model, data, q)
        potentials.append(
            -sum(
                model.inertias[j].mass * float(gravity @ data.oMi[j].act(model.inertias[j].lever))
                for j in range(1, model.njoints)
            )
        )
    return np.array(torques), np.array(potentials)


def _mechanisms():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # mimic joints loaded as independent joints
        yield "ur5", sb.Mechanism.from_robot("ur5")
        yield "quaglia_yin_r3", sb.Mechanism.from_urdf("urdf/quaglia_yin_r3.urdf")
        yield "four_bar", sb.Mechanism.from_urdf("urdf/sit_to_stand_four_bar.urdf")
        yield "four_bar_mimic", sb.Mechanism.from_urdf("urdf/sit_to_stand_four_bar.urdf", mimic=True)
        yield "parallelogram_mimic", sb.Mechanism.from_urdf("urdf/parallelogram_arm.urdf", mimic=True)


@pytest.mark.parametrize(
    "name,mechanism", list(_mechanisms()), ids=lambda value: value if isinstance(value, str) else ""
)
def test_batched_gravity_and_potential_equal_the_loop(name, mechanism):
    configurations = sb.Workspace.sobol(mechanism, 300, seed=2).configurations
    torque, potential = gravity_and_potential(mechanism.model, configurations)
    expected_torque, expected_potential = _loop(mechanism.model, configurations)
    assert torque.shape == expected_torque.shape and potential.shape == expected_potential.shape
    scale = max(np.max(np.abs(expected_torque)), 1.0)
    assert np.max(np.abs(torque - expected_torque)) <= 1e-12 * scale
    scale = max(np.max(np.abs(expected_potential)), 1.0)
    assert np.max(np.abs(potential - expected_potential)) <= 1e-12 * scale
