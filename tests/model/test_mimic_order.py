"""Mimic joints in any order: a URDF whose mimic joint Pinocchio's parser reaches before its primary
joint loads (springbalance reorders it), with the torques of the same URDF written in the working order."""

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf" / "structure_ii.urdf"
#: structure II with a mass on the transfer crank, so that the coupling shows in the torques
CRANK_MASS = (
    '<origin xyz="0 0 0" rpy="0 0 0"/>\n      <mass value="0.05"/>',
    '<origin xyz="0.12 0 0.03"/><mass value="0.7"/>',
)


def _texts(text: str, mimic: str, working: str) -> tuple[str, str]:
    """``text`` as it is (its mimic joint ``mimic`` sorts before its primary) and with the mimic joint renamed ``working``."""
    return text, text.replace(f'"{mimic}"', f'"{working}"')


def _torques(text: str, joint_values: np.ndarray) -> tuple[sb.Mechanism, np.ndarray]:
    mechanism = sb.Mechanism.from_urdf_string(text, mimic=True, gravity=9.81)
    return mechanism, sb.Workspace.from_array(mechanism, joint_values).kinematics().gravity_torque


@pytest.mark.parametrize("crank_mass", [False, True])
def test_a_mimic_joint_named_before_its_primary_loads_with_the_working_orders_torques(crank_mass):
    text = URDF.read_text()
    if crank_mass:
        assert CRANK_MASS[0] in text
        text = text.replace(*CRANK_MASS)  # the hub on the axis becomes 0.7 kg off it
    reordered, working = _texts(text, "a_transfer", "z_transfer")
    with pytest.raises(Exception, match="not in the kinematic tree"):  # what Pinocchio alone does with it
        pin.buildModelFromXML(reordered, mimic=True)
    joint_values = np.random.default_rng(3).uniform(-1.5, 1.5, (40, 2))
    mechanism, torque = _torques(reordered, joint_values)
    reference, expected = _torques(working, joint_values)
    assert mechanism.joint_names == reference.joint_names == ["shoulder", "elbow"]
    assert "a_transfer" in mechanism.model.names and mechanism.model.existFrame("a_transfer")
    assert mechanism.summary()["joints"][-1]["mimic"]["joint"] == "elbow"
    np.testing.assert_allclose(torque, expected, rtol=0, atol=1e-12 * np.max(np.abs(expected)))
    if crank_mass:  # the crank keeps link2's absolute angle: its weight loads the elbow (and the shoulder)
        assert np.max(np.abs(torque - _torques(URDF.read_text(), joint_values)[1])) > 0.1


def _link(name: str, mass: float = 0.0, x: float = 0.0) -> str:
    inertial = (
        f'<inertial><origin xyz="{x} 0 0"/><mass value="{mass}"/>'
        '<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>'
    )
    return f'<link name="{name}">{inertial if mass else ""}</link>'


def _joint(name: str, parent: str, child: str, x: float = 0.0, mimic: str | None = None) -> str:
    coupling = f'<mimic joint="{mimic}" multiplier="-0.5" offset="0.2"/>' if mimic else ""
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{x} 0 0"/><axis xyz="0 -1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/>'
        f"{coupling}</joint>"
    )


def test_a_mimic_joint_on_another_branch_from_the_root_loads():
    # the primary "c_elbow" sits below "b_arm"; its mimic "a_crank" hangs from the base, a branch
    # that Pinocchio (siblings by name) would number first
    def robot(crank: str) -> str:
        return (
            '<robot name="branches">'
            + _link("base")
            + _link("upper", 1.0, 0.2)
            + _link("fore", 0.5, 0.15)
            + _link("crank", 0.3, 0.1)
            + _joint("b_arm", "base", "upper")
            + _joint("c_elbow", "upper", "fore", x=0.4)
            + _joint(crank, "base", "crank", mimic="c_elbow")
            + "</robot>"
        )

    joint_values = np.random.default_rng(4).uniform(-1.5, 1.5, (30, 2))
    mechanism, torque = _torques(robot("a_crank"), joint_values)
    _, expected = _torques(robot("z_crank"), joint_values)
    assert mechanism.joint_names == ["b_arm", "c_elbow"]
    np.testing.assert_allclose(torque, expected, rtol=0, atol=1e-12 * np.max(np.abs(expected)))


def test_a_mimic_joint_above_its_primary_is_refused_with_the_fix():
    text = (
        '<robot name="upside">'
        + _link("base")
        + _link("upper", 1.0, 0.2)
        + _link("fore", 0.5, 0.15)
        + _joint("shoulder", "base", "upper", mimic="elbow")
        + _joint("elbow", "upper", "fore", x=0.4)
        + "</robot>"
    )
    with pytest.raises(
        sb.InputError, match=r"mimic joint 'shoulder' is an ancestor of its primary joint 'elbow'"
    ) as error:
        sb.Mechanism.from_urdf_string(text, mimic=True)
    assert "\n" not in str(error.value) and "make 'elbow' the mimic of 'shoulder'" in str(error.value)
