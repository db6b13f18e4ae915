"""Seed 002's structure II (examples/structure_ii.yaml, urdf/structure_ii.urdf): two constant forces along the
fixed vertical balance a two-link arm exactly, one on link1 and one on a transfer crank that keeps link2's
absolute angle (a joint that mimics the elbow). The paper's conditions, computed here from the URDF's masses
and lengths:

    F1 b1 = (m1 r1 + m2 l1) g,        F2 b2 = m2 r2 g.
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np
import pytest

from springbalance.io.config import load_config, read_config_file

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "structure_ii.yaml"


def _urdf_numbers() -> dict[str, float]:
    root = ElementTree.parse(ROOT / "urdf" / "structure_ii.urdf").getroot()

    def inertial(link: str) -> tuple[float, float]:
        element = root.find(f"link[@name='{link}']/inertial")
        assert element is not None
        x, y, z = (float(v) for v in element.find("origin").get("xyz").split())
        assert y == z == 0  # the centre of mass lies on the link's line
        return float(element.find("mass").get("value")), x

    (m1, r1), (m2, r2) = inertial("link1"), inertial("link2")
    l1 = float(root.find("joint[@name='elbow']/origin").get("xyz").split()[0])
    mimic = root.find("joint[@name='a_transfer']/mimic")
    assert mimic.get("joint") == "elbow" and float(mimic.get("multiplier")) == 1.0
    return {"m1": m1, "r1": r1, "m2": m2, "r2": r2, "l1": l1}


def test_structure_ii_balances_exactly_with_the_papers_forces():
    numbers = _urdf_numbers()
    record = read_config_file(EXAMPLE)
    g = float(record["mechanism"]["gravity"])
    arms = {spring["name"]: spring["a"]["point"][0] for spring in record["springs"]}  # b1, b2 [m]
    assert all(spring["direction"] == [0, 0, 1] for spring in record["springs"])  # both along the world's vertical
    expected_f1 = (numbers["m1"] * numbers["r1"] + numbers["m2"] * numbers["l1"]) * g / arms["f1"]
    expected_f2 = numbers["m2"] * numbers["r2"] * g / arms["f2"]
    result = load_config(EXAMPLE).solve()
    assert result.variables["f1.force"] == pytest.approx(expected_f1, rel=1e-9)
    assert result.variables["f2.force"] == pytest.approx(expected_f2, rel=1e-9)
    peak = result.metrics()["objectives"]["peak"]
    assert peak["before"] > 1.0  # the arm is far from balanced without the forces [N·m]
    assert peak["after"] <= 1e-9 * peak["before"]


def test_mujoco_holds_the_exported_structure_ii(tmp_path):
    """MuJoCo, with the transfer crank's joint set to the elbow's (its equality constraint off, the crank's
    torque added to the elbow's as the export's warning says), needs no torque to hold the arm."""
    mujoco = pytest.importorskip("mujoco")
    result = load_config(EXAMPLE).solve()
    result.to_mjcf(tmp_path / "structure_ii.xml")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "structure_ii.xml"))
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_EQUALITY
    data = mujoco.MjData(model)
    joint = {
        name: mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) for name in ("shoulder", "elbow", "a_transfer")
    }
    residual, gravity = [], []
    for shoulder, elbow in np.random.default_rng(1).uniform(-1.5, 1.5, (40, 2)):
        for name, value in (("shoulder", shoulder), ("elbow", elbow), ("a_transfer", elbow)):
            data.qpos[model.jnt_qposadr[joint[name]]] = value
        data.qvel[:] = 0
        data.qacc[:] = 0
        mujoco.mj_inverse(model, data)
        mujoco.mj_fwdActuation(model, data)
        held = data.qfrc_inverse - data.qfrc_actuator  # gravity minus the exported forces
        dof = {name: model.jnt_dofadr[index] for name, index in joint.items()}
        residual.append([held[dof["shoulder"]], held[dof["elbow"]] + held[dof["a_transfer"]]])
        gravity.append(data.qfrc_inverse[dof["shoulder"]])
    assert np.max(np.abs(gravity)) > 1.0
    assert np.max(np.abs(residual)) <= 1e-9 * np.max(np.abs(gravity))
