"""MuJoCo as the independent engine of the export tests: the holding torque of an exported model.

``mj_inverse`` at zero velocity and acceleration gives ``qfrc_inverse = M qacc + c - qfrc_passive -
qfrc_constraint``; minus the constant forces of the spring actuators (``qfrc_actuator``, which
``mj_inverse`` does not subtract) it is the torque the motors must add to hold the arm: gravity
minus the tendon and joint springs. Contacts are switched off: the holding torque of docs/model.md
§4 is that of the arm alone.
"""

from __future__ import annotations

import mujoco
import numpy as np


def mujoco_holding_torque(path, mechanism, joint_values) -> np.ndarray:
    """Holding torque (N×nv, the mechanism's joint order) from MuJoCo's inverse dynamics."""
    model = mujoco.MjModel.from_xml_path(str(path))
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    data = mujoco.MjData(model)
    ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint.name) for joint in mechanism.joints]
    assert min(ids) >= 0
    torques = []
    for row in np.atleast_2d(joint_values):
        for column, joint_id in enumerate(ids):
            data.qpos[model.jnt_qposadr[joint_id]] = row[column]
        data.qvel[:] = 0
        data.qacc[:] = 0
        mujoco.mj_inverse(model, data)
        mujoco.mj_fwdActuation(model, data)
        assert data.nefc == 0  # no joint limit or other constraint force enters the comparison
        total = data.qfrc_inverse - data.qfrc_actuator
        torques.append([total[model.jnt_dofadr[joint_id]] for joint_id in ids])
    return np.array(torques)


def random_inside(mechanism, ranges, n=100, seed=0):
    """``n`` uniform random poses inside the box ``ranges`` (joint name → [lower, upper] [rad])."""
    rng = np.random.default_rng(seed)
    lower = np.array([ranges[joint.name][0] for joint in mechanism.joints])
    upper = np.array([ranges[joint.name][1] for joint in mechanism.joints])
    return lower + (upper - lower) * rng.random((n, mechanism.nv))
