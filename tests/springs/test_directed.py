"""Forces along a fixed direction (springs/laws/directed.py, docs/model.md §3.11): a constant force or a gas
spring whose line of action is a guide's direction, not the line between two anchors.

References here are hand geometry of the two-link planar arm (urdf/two_link_planar.urdf: link1 0.5 m,
both joints about (0, -1, 0), angles counter-clockwise in the x-z plane): an anchor at (b, 0, 0) of
link1 sits at b (cos θ1, 0, sin θ1); an anchor at (c, 0, 0) of link2 sits at l1 (cos θ1, 0, sin θ1) +
c (cos(θ1+θ2), 0, sin(θ1+θ2)). The gravity torque is Pinocchio's.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.springs import SPRING_TYPES, spring_from_dict

URDF = Path(__file__).resolve().parents[2] / "urdf"
L1 = 0.5  # link1 of two_link_planar [m]


def _arm(n: int = 9):
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.grid(mechanism, n)
    return mechanism, workspace


def _spring_torque(springs, n: int = 9):
    """The springs' share of the holding torque over a grid (N×2) [N·m], and the joint values (N×2) [rad]."""
    mechanism, workspace = _arm(n)
    tau = sb.DesignProblem(mechanism, workspace, springs).evaluate(np.zeros(0)).tau
    return tau - workspace.kinematics().gravity_torque, workspace.joint_values


def test_the_laws_register_and_their_force_is_minus_the_potentials_slope():
    assert SPRING_TYPES["directed_force"] is sb.DirectedForce and SPRING_TYPES["directed_gas"] is sb.DirectedGas
    anchor = sb.Anchor("link1", [0.1, 0, 0])
    gas = sb.DirectedGas(anchor, direction=[0, 0, 1], stiffness=300.0, free_length=0.2, preload=40.0)
    values, s, h = {"stiffness": 300.0, "free_length": 0.2, "preload": 40.0}, np.linspace(-0.3, 0.3, 13), 1e-6
    slope = (gas.potential(s + h, values) - gas.potential(s - h, values)) / (2 * h)
    np.testing.assert_allclose(gas.force(s, values), -slope, rtol=1e-8)
    np.testing.assert_allclose(gas.force(s, values), 40.0 + 300.0 * (0.2 - s))  # F0 + k (l0 - s)
    constant = sb.DirectedForce(anchor, direction=[0, 0, 1], force=25.0)
    np.testing.assert_allclose(constant.potential(s, {"force": 25.0}), -25.0 * s)


def test_a_force_along_the_world_vertical_on_link1_holds_minus_f_b_cos_theta1():
    force, b = 30.0, 0.2  # [N] up, [m] along link1
    spring = sb.DirectedForce(sb.Anchor("link1", [b, 0, 0]), direction=[0, 0, 1], force=force)
    torque, q = _spring_torque([spring])
    # V = -F z_p = -F b sin θ1: τ1 = -F b cos θ1, τ2 = 0
    np.testing.assert_allclose(torque[:, 0], -force * b * np.cos(q[:, 0]), atol=1e-12)
    np.testing.assert_allclose(torque[:, 1], 0.0, atol=1e-12)


def test_a_guide_on_link1_takes_the_reaction_its_moment_cancels_the_shoulder_torque():
    # guide: link1's x axis (along the link, from the shoulder); anchor at (c, 0, 0) of link2:
    # s = u·(p − o) = l1 + c cos θ2, whatever θ1
    c, force = 0.15, 20.0
    constant = sb.DirectedForce(sb.Anchor("link2", [c, 0, 0]), direction=[1, 0, 0], guide="link1", force=force)
    torque, q = _spring_torque([constant])
    np.testing.assert_allclose(torque[:, 0], 0.0, atol=1e-12)  # V = -F s does not depend on θ1
    np.testing.assert_allclose(torque[:, 1], force * c * np.sin(q[:, 1]), atol=1e-12)  # dV/dθ2 = F c sin θ2
    k, l0, f0 = 400.0, 0.7, 15.0
    gas = sb.DirectedGas(
        sb.Anchor("link2", [c, 0, 0]),
        direction=[1, 0, 0],
        guide="link1",
        stiffness=k,
        free_length=l0,
        preload=f0,
        stays_compressed=False,
    )
    torque, q = _spring_torque([gas])
    s = L1 + c * np.cos(q[:, 1])
    np.testing.assert_allclose(torque[:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(torque[:, 1], (f0 + k * (l0 - s)) * c * np.sin(q[:, 1]), atol=1e-10)


def test_a_tilted_direction_gives_the_projection_of_the_anchors_motion():
    u = np.array([0.6, 0.0, 0.8])
    force, b = 12.0, 0.3
    spring = sb.DirectedForce(sb.Anchor("link1", [b, 0, 0]), direction=u, force=force)
    torque, q = _spring_torque([spring])
    # V = -F u·p = -F b (0.6 cos θ1 + 0.8 sin θ1)
    np.testing.assert_allclose(torque[:, 0], -force * b * (-0.6 * np.sin(q[:, 0]) + 0.8 * np.cos(q[:, 0])), atol=1e-12)


def test_record_round_trip_and_clear_errors():
    record = {
        "name": "slider",
        "type": "directed_gas",
        "a": {"body": "link2", "point": [0.1, 0, 0]},
        "direction": [1, 0, 0],
        "guide": "link1",
        "stiffness": {"lower": 0, "upper": 500},
        "free_length": 0.6,
        "stroke": 0.2,
    }
    spring = spring_from_dict(record)
    again = spring_from_dict(json.loads(json.dumps(spring.to_dict())))
    assert again.to_dict() == spring.to_dict() and again.guide == "link1" and again.stroke == 0.2
    with pytest.raises(sb.InputError, match=r"slider.*direction.*unit vector.*norm 2"):
        spring_from_dict({**record, "direction": [0, 2, 0]})
    with pytest.raises(sb.InputError, match="direction"):
        spring_from_dict({key: value for key, value in record.items() if key != "direction"})
    with pytest.raises(sb.InputError, match="unknown key 'b'"):
        spring_from_dict({**record, "b": {"body": "universe"}})
    mechanism, workspace = _arm(3)
    with pytest.raises(sb.InputError, match="spring 'slider': unknown body 'link9'"):
        sb.DesignProblem(mechanism, workspace, [spring_from_dict({**record, "guide": "link9"})])
    with pytest.raises(sb.InputError, match="anchor and its guide are both on body 'link2'"):
        sb.DesignProblem(mechanism, workspace, [spring_from_dict({**record, "guide": "link2"})])


def test_mujoco_holds_the_exported_forces_as_the_tool_does(tmp_path):
    pytest.importorskip("mujoco")
    from mujoco_helpers import mujoco_holding_torque

    mechanism, workspace = _arm(7)
    springs = [
        sb.DirectedForce(sb.Anchor("link1", [0.2, 0, 0.01]), direction=[0.6, 0, 0.8], force=35.0),
        sb.DirectedGas(
            sb.Anchor("link2", [0.15, 0, 0.02]),
            direction=[1, 0, 0],
            guide="link1",
            stiffness=400.0,
            free_length=0.7,
            preload=15.0,
            stays_compressed=False,
        ),
    ]
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, springs), np.zeros(0))
    result.to_mjcf(tmp_path / "arm.xml")
    expected = result.evaluation.tau
    torque = mujoco_holding_torque(tmp_path / "arm.xml", mechanism, workspace.joint_values)
    np.testing.assert_allclose(torque, expected, rtol=0, atol=1e-9 * np.max(np.abs(expected)))


def test_the_urdf_export_keeps_the_direction_and_the_guide(tmp_path):
    mechanism, workspace = _arm(3)
    spring = sb.DirectedForce(
        sb.Anchor("link2", [0.1, 0, 0]), name="slider", direction=[1, 0, 0], guide="link1", force=9.0
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    result.to_urdf(tmp_path / "arm.urdf")
    from springbalance.io.urdf import springs_from_urdf

    (again,) = springs_from_urdf(tmp_path / "arm.urdf")
    assert isinstance(again, sb.DirectedForce) and again.guide == "link1"
    assert again.direction.tolist() == [1.0, 0.0, 0.0] and again.parameters["force"] == 9.0
