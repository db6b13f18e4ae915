"""Export of a pseudo-base arm (issue 29), its pseudo-bases keeping the orientation or only the vertical: the
URDF carries the mimic chains, the MJCF joint equality constraints, and MuJoCo's holding torque equals the
tool's to 1e-9 of the torque scale.

MuJoCo gives every chain joint a DOF of its own, tied to its primary joint by an equality constraint
(``q_mimic = -q_primary``). At a pose that meets every constraint, with zero velocity and acceleration,
the constraint forces vanish and, by virtual work, the holding torque of primary joint j is MuJoCo's
torque on j minus the torques on the chain joints that mimic it (multiplier −1). Drake reads the exported
URDF the same way (its continuous plant ignores ``<mimic>``); that check skips where Drake is not installed
(the project's environment does not carry it: ``pip install drake``; it passed with drake 1.51.1 at 2.7e-13 N·m).
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from springbalance.design.problem import DesignProblem
from springbalance.results.result import DesignResult

ROOT = Path(__file__).resolve().parents[2]
KR = ROOT / "urdf" / "kr_like_6r.urdf"
BASES = ["a2", "a3", {"joint": "a4", "mass": 0.7, "com": [0.02, -0.01, 0.05]}, "a5", {"joint": "a6", "mass": 0.3}]
#: mimic joints per kind of pseudo-base: pb_a2 … pb_a6 undo 1 … 5 joints; keeping only the vertical, a1 (a vertical
#: axis at the root) is not undone, so 0 … 4
MIMICS = {"orientation": 1 + 2 + 3 + 4 + 5, "vertical": 0 + 1 + 2 + 3 + 4}


@pytest.fixture(scope="module", params=["orientation", "vertical"])
def design(request):
    bases = [
        {"joint": base, "keep": request.param} if isinstance(base, str) else {**base, "keep": request.param}
        for base in BASES
    ]
    mechanism = sb.Mechanism.from_urdf(KR, pseudo_bases=bases)
    rng = np.random.default_rng(5)
    springs = [
        sb.ZeroFreeLengthSpring(
            sb.Anchor(f"pb_a{i}", rng.uniform(-0.2, 0.2, 3)),
            sb.Anchor(f"link{i}", rng.uniform(-0.2, 0.2, 3)),
            f"s{i}",
            stiffness=float(rng.uniform(100, 2000)),
        )
        for i in range(2, 7)
    ]
    lower = np.array([j.lower for j in mechanism.joints])
    upper = np.array([j.upper for j in mechanism.joints])
    poses = lower + (upper - lower) * rng.random((30, mechanism.nv))
    workspace = sb.Workspace.from_array(mechanism, poses, ordered=False)
    return DesignResult(DesignProblem(mechanism, workspace, springs), np.zeros(0)), poses


def _mujoco_holding(path, mechanism, poses):
    model = mujoco.MjModel.from_xml_path(str(path))
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    data = mujoco.MjData(model)
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, i) for i in range(model.njnt)]
    primaries = mechanism.joint_names
    # the chain joints are pb_<J>__undo_<primary>; each mimics its primary with multiplier -1
    followers = {name: name.rsplit("__undo_", 1)[1] for name in names if "__undo_" in name}
    assert len(followers) == MIMICS[mechanism.pseudo_bases[0].keep]
    torques = []
    for row in poses:
        value = dict(zip(primaries, row))
        for joint_id, name in enumerate(names):
            data.qpos[model.jnt_qposadr[joint_id]] = value[name] if name in value else -value[followers[name]]
        data.qvel[:] = 0
        data.qacc[:] = 0
        mujoco.mj_inverse(model, data)
        mujoco.mj_fwdActuation(model, data)
        total = data.qfrc_inverse - data.qfrc_actuator
        tau = {name: total[model.jnt_dofadr[i]] for i, name in enumerate(names)}
        torques.append([tau[p] - sum(tau[f] for f, primary in followers.items() if primary == p) for p in primaries])
    return np.array(torques)


def test_mujoco_holding_torque_of_a_pseudo_base_arm_matches(design, tmp_path):
    result, poses = design
    report = result.to_mjcf(tmp_path / "kr.xml")
    keep = result.problem.mechanism.pseudo_bases[0].keep
    assert sum("mimic joint" in warning for warning in report.warnings) == MIMICS[keep]
    measured = _mujoco_holding(tmp_path / "kr.xml", result.problem.mechanism, poses)
    expected = result.residual_torque(poses)
    scale = float(np.max(np.abs(expected)))
    assert scale > 1
    assert np.max(np.abs(measured - expected)) <= 1e-9 * scale


def test_exported_urdf_has_the_mimic_chains_and_loads_back(design, tmp_path):
    result, poses = design
    path = tmp_path / "kr.urdf"
    result.to_urdf(path)
    text = path.read_text()
    keep = result.problem.mechanism.pseudo_bases[0].keep
    assert text.count("<mimic ") == MIMICS[keep] and 'multiplier="-1"' in text
    again = sb.Mechanism.from_urdf(path, mimic=True)  # a plain URDF now: no pseudo_bases needed
    assert again.joint_names == result.problem.mechanism.joint_names
    mechanism = result.problem.mechanism
    data, data_again = mechanism.model.createData(), again.model.createData()
    for q in mechanism.configurations(poses[:5]):
        tau = pin.computeGeneralizedGravity(mechanism.model, data, q)
        np.testing.assert_allclose(pin.computeGeneralizedGravity(again.model, data_again, q), tau, rtol=0, atol=1e-12)


def test_saved_design_rebuilds_its_pseudo_bases(design, tmp_path):
    result, poses = design
    path = result.save(tmp_path / "design.json")
    again = sb.DesignResult.load(path)
    assert [b.to_dict() for b in again.problem.mechanism.pseudo_bases] == [
        b.to_dict() for b in result.problem.mechanism.pseudo_bases
    ]
    np.testing.assert_allclose(again.residual_torque(poses), result.residual_torque(poses), rtol=0, atol=1e-12)


def _drake_holding(path, result, poses):
    """Holding torque from Drake's kinematics of the exported URDF: gravity (``CalcGravityGeneralizedForces``) and
    each zero-free-length spring ``k (x_b - x_a)ᵀ (J_b - J_a)`` between its anchor links, the chain joints
    projected on their primaries by virtual work as for MuJoCo. Drake's continuous plant ignores ``<mimic>``
    (it warns), so every chain joint is a DOF here, set to ``-q_primary``."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import JacobianWrtVariable

    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("base_link"))
    plant.mutable_gravity_field().set_gravity_vector(result.problem.mechanism.gravity)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    joints = [plant.get_joint(index) for index in plant.GetJointIndices() if plant.get_joint(index).num_velocities()]
    primaries = result.problem.mechanism.joint_names
    followers = {j.name(): j.name().rsplit("__undo_", 1)[1] for j in joints if "__undo_" in j.name()}
    world = plant.world_frame()
    torques = []
    for row in poses:
        value = dict(zip(primaries, row))
        q = np.zeros(plant.num_positions())
        for joint in joints:
            q[joint.position_start()] = (
                value[joint.name()] if joint.name() in value else -value[followers[joint.name()]]
            )
        plant.SetPositions(context, q)
        holding = -plant.CalcGravityGeneralizedForces(context)
        for spring, record in zip(result.problem.springs, result.springs):
            ends = []
            for end in ("a", "b"):
                frame = plant.GetFrameByName(f"{spring.name}_anchor_{end}")
                x = plant.CalcPointsPositions(context, frame, np.zeros(3), world)[:, 0]
                jacobian = plant.CalcJacobianTranslationalVelocity(
                    context, JacobianWrtVariable.kV, frame, np.zeros(3), world, world
                )
                ends.append((x, jacobian))
            (xa, ja), (xb, jb) = ends
            holding += record["stiffness"] * (xb - xa) @ (jb - ja)
        tau = {joint.name(): holding[joint.velocity_start()] for joint in joints}
        torques.append([tau[p] - sum(tau[f] for f, primary in followers.items() if primary == p) for p in primaries])
    return np.array(torques)


def test_drake_holding_torque_of_a_pseudo_base_arm_matches(design, tmp_path):
    pytest.importorskip(
        "pydrake",
        reason="Drake is not installed (a test extra; no wheel for this platform?): the MuJoCo check runs",
    )
    result, poses = design
    path = tmp_path / "kr.urdf"
    result.to_urdf(path)
    measured = _drake_holding(path, result, poses)
    expected = result.residual_torque(poses)
    scale = float(np.max(np.abs(expected)))
    assert np.max(np.abs(measured - expected)) <= 1e-9 * scale
