"""Export of a balanced arm (issue 7): URDF with anchor links, MuJoCo model with tendon springs.

MuJoCo is the independent engine here: its inverse dynamics at zero velocity and acceleration
(``mj_inverse``; ``qfrc_inverse = M qacc + c - qfrc_passive - qfrc_constraint``) minus the
constant forces of the spring actuators (``qfrc_actuator``, which ``mj_inverse`` does not
subtract) is the torque the motors must add to hold the arm: gravity minus the tendon and
joint springs. Contacts are switched off for this check: the holding torque of docs/model.md §4
is that of the arm alone, and the UR5's collision meshes touch at some random poses.
"""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import springbalance as sb
from mujoco_helpers import mujoco_holding_torque, random_inside
from springbalance.cli import main
from springbalance.design.problem import DesignProblem
from springbalance.export.common import anchor_link_name
from springbalance.export.urdf import sidecar_path
from springbalance.io.config import load_config
from springbalance.io.urdf import springs_from_urdf
from springbalance.model import robots
from springbalance.results.result import DesignResult

ROOT = Path(__file__).resolve().parents[2]
TWO_LINK = ROOT / "urdf" / "two_link_planar.urdf"
R2 = ROOT / "urdf" / "single_link_r2.urdf"
RELATIVE = 1e-9


def assert_same_holding_torque(result, mjcf, joint_values):
    expected = result.residual_torque(joint_values)
    measured = mujoco_holding_torque(mjcf, result.problem.mechanism, joint_values)
    scale = float(np.max(np.abs(expected)))
    assert scale > 0
    assert np.max(np.abs(measured - expected)) <= RELATIVE * scale


# ---------------------------------------------------------------------- designs
@pytest.fixture(scope="module")
def two_link():
    return load_config(ROOT / "examples" / "two_link.yaml").solve(starts=1, progress=False)


@pytest.fixture(scope="module")
def ur5():
    mechanism = sb.Mechanism.from_robot("ur5")
    workspace = sb.Workspace.sobol(mechanism, 256, seed=1)
    box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)  # noqa: E731
    pairs = [
        ("universe", "upper_arm_link"),
        ("universe", "forearm_link"),
        ("upper_arm_link", "forearm_link"),
        ("shoulder_link", "forearm_link"),
    ]
    springs = [
        sb.ExtensionSpring(
            sb.Anchor(a, box()),
            sb.Anchor(b, box()),
            f"s{i + 1}",
            stiffness=sb.Free(0, 5000),
            free_length=sb.Free(0.05, 1.0),
        )
        for i, (a, b) in enumerate(pairs)
    ]
    result = sb.solve(sb.DesignProblem(mechanism, workspace, springs), starts=2, progress=False)
    assert result.metrics()["objectives"]["rms"]["reduction_percent"] > 90
    return result


def fixed_design(mechanism, springs, joint_values):
    workspace = sb.Workspace.from_array(mechanism, joint_values, ordered=False)
    return DesignResult(DesignProblem(mechanism, workspace, springs), np.zeros(0))


# ---------------------------------------------------------------------- must-hold 1: MuJoCo agrees
def test_two_link_mujoco_holding_torque_matches(two_link, tmp_path):
    report = two_link.to_mjcf(tmp_path / "two_link.xml")
    assert report.warnings == []
    mechanism = two_link.problem.mechanism
    poses = random_inside(mechanism, {"shoulder": np.radians([-90, 90]), "elbow": np.radians([-120, 120])})
    assert_same_holding_torque(two_link, tmp_path / "two_link.xml", poses)


def test_ur5_four_springs_mujoco_holding_torque_matches(ur5, tmp_path):
    ur5.to_mjcf(tmp_path / "ur5.xml")
    mechanism = ur5.problem.mechanism
    ranges = {joint.name: (joint.lower, joint.upper) for joint in mechanism.joints}
    poses = random_inside(mechanism, ranges, seed=1)
    assert_same_holding_torque(ur5, tmp_path / "ur5.xml", poses)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "ur5.xml"))
    assert model.ntendon == 4
    # the arm's mass is the URDF's, body by body
    urdf = yourdfpy.URDF.load(str(robots.robot_urdf("ur5")), build_scene_graph=False, load_meshes=False)
    for link in urdf.robot.links:
        if link.inertial is not None and link.inertial.mass:
            body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, link.name)
            assert model.body_mass[body] == link.inertial.mass


def test_every_law_matches_mujoco(tmp_path):
    """Each spring law, preloads, k = 0 cases and spring mass, against MuJoCo's inverse dynamics."""
    mechanism = sb.Mechanism.from_urdf(TWO_LINK)
    up, link1, link2 = (
        (lambda p: sb.Anchor("universe", p)),
        (lambda p: sb.Anchor("link1", p)),
        (lambda p: sb.Anchor("link2", p)),
    )
    springs = [
        sb.ZeroFreeLengthSpring(up([0, 0, 0.2]), link1([0.3, 0, 0]), "zfl", stiffness=80.0, mass=0.3),
        sb.ExtensionSpring(
            up([0.05, 0, 0.4]),
            link2([0.2, 0, 0.01]),
            "ext",
            stiffness=120.0,
            free_length=0.1,
            initial_tension=15.0,
            keep_tension=False,
        ),
        sb.ExtensionSpring(
            link1([0.1, 0, 0.05]),
            link2([0.1, 0, 0.0]),
            "ext0",
            stiffness=0.0,
            free_length=0.1,
            initial_tension=4.0,
            keep_tension=False,
        ),
        sb.CompressionSpring(
            up([-0.1, 0, -0.2]),
            link1([0.2, 0, 0]),
            "comp",
            stiffness=300.0,
            free_length=0.9,
            preload=20.0,
            stays_compressed=False,
        ),
        sb.GasSpring(
            link1([0.05, 0, -0.05]),
            link2([0.15, 0, 0]),
            "gas",
            stiffness=50.0,
            free_length=0.6,
            preload=40.0,
            stays_compressed=False,
        ),
        sb.ConstantForceSpring(up([0.3, 0, 0.5]), link2([0.35, 0, 0]), "cf", force=6.0),
        sb.TorsionalSpring("elbow", "tor", stiffness=3.0, neutral_angle=0.4, preload=-1.5),
        sb.TorsionalSpring("elbow", "tor2", stiffness=1.0, neutral_angle=-0.7, preload=0.5),  # two on one joint
        sb.TorsionalSpring("shoulder", "tor0", stiffness=0.0, neutral_angle=0.0, preload=2.5),
    ]
    poses = random_inside(mechanism, {"shoulder": (-1.5, 1.5), "elbow": (-2.5, 2.5)}, seed=2)
    result = fixed_design(mechanism, springs, poses)
    report = result.to_mjcf(tmp_path / "laws.xml")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "laws.xml"))
    assert model.ntendon == 6 and model.nu == 3  # ext0 and cf: constant forces; tor0: constant torque
    assert_same_holding_torque(result, tmp_path / "laws.xml", poses)
    # the extension springs shorter than l0 somewhere, and the compression/gas springs longer, are reported
    reported = " ".join(report.warnings)
    for name in ("'ext'", "'ext0'", "'comp'", "'gas'"):
        lengths = result.evaluation.lengths[:, [s.name for s in springs].index(name.strip("'"))]
        assert (name in reported) == bool(
            np.any(lengths < 0.1) if "ext" in name else np.any(lengths > result.spring(name.strip("'"))["free_length"])
        )


def test_exactly_balanced_link_is_balanced_in_mujoco(tmp_path):
    """R2 link, zero-free-length spring with k a b = m g c (docs/model.md §9): MuJoCo holds it with no torque."""
    mechanism = sb.Mechanism.from_urdf(R2, gravity=9.8)
    a, b, m, c, g = 0.1, 0.2, 1.0, 0.25, 9.8
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, a]), sb.Anchor("link1", [b, 0, 0]), "s1", stiffness=m * g * c / (a * b)
    )
    poses = np.linspace(-np.pi, np.pi, 37)[:, None]
    result = fixed_design(mechanism, [spring], poses)
    result.to_mjcf(tmp_path / "r2.xml")
    holding = mujoco_holding_torque(tmp_path / "r2.xml", mechanism, poses)
    assert np.max(np.abs(holding)) < 1e-12 * m * g * c
    # and without the spring MuJoCo holds the bare weight m g c cos q
    bare = fixed_design(mechanism, [sb.ZeroFreeLengthSpring(spring.a, spring.b, "s1", stiffness=0.0)], poses)
    bare.to_mjcf(tmp_path / "bare.xml")
    weight = mujoco_holding_torque(tmp_path / "bare.xml", mechanism, poses)[:, 0]
    np.testing.assert_allclose(weight, m * g * c * np.cos(poses[:, 0]), atol=1e-12)


def test_gas_spring_beyond_its_stroke_is_reported(tmp_path):
    mechanism = sb.Mechanism.from_urdf(TWO_LINK)
    gas = sb.GasSpring(
        sb.Anchor("universe", [-0.1, 0, -0.2]),
        sb.Anchor("link1", [0.2, 0, 0]),
        "g1",
        stiffness=50.0,
        free_length=0.5,
        preload=40.0,
        stroke=0.05,
    )
    poses = random_inside(mechanism, {"shoulder": (-1.5, 1.5), "elbow": (0, 0)}, n=20)
    result = fixed_design(mechanism, [gas], poses)
    report = result.to_mjcf(tmp_path / "gas.xml")
    assert any("'g1'" in warning and "stroke" in warning for warning in report.warnings)
    # reported, not changed: MuJoCo still has the linear law
    assert_same_holding_torque(result, tmp_path / "gas.xml", poses)


def test_mimic_joint_becomes_an_equality_constraint(tmp_path):
    """Elbow mimicking the shoulder (multiplier -1): by virtual work the independent joint's holding
    torque is MuJoCo's torque on the shoulder minus its torque on the elbow."""
    text = TWO_LINK.read_text().replace(
        '<axis xyz="0 -1 0"/>\n    <limit lower="-2.6179938779914944"',
        '<axis xyz="0 -1 0"/>\n    <mimic joint="shoulder" multiplier="-1.0" offset="0.0"/>\n'
        '    <limit lower="-2.6179938779914944"',
    )
    path = tmp_path / "mimic.urdf"
    path.write_text(text)
    mechanism = sb.Mechanism.from_urdf(path, mimic=True)
    assert mechanism.joint_names == ["shoulder"]
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link2", [0.3, 0, 0]), "s1", stiffness=200.0
    )
    poses = np.linspace(-1.4, 1.4, 15)[:, None]
    result = fixed_design(mechanism, [spring], poses)
    report = result.to_mjcf(tmp_path / "mimic.xml")
    assert any("mimic joint 'elbow'" in warning for warning in report.warnings)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "mimic.xml"))
    data = mujoco.MjData(model)
    holding = []
    for (shoulder,) in poses:
        data.qpos[:] = [shoulder, -shoulder]
        data.qvel[:] = 0
        data.qacc[:] = 0
        mujoco.mj_inverse(model, data)
        holding.append(data.qfrc_inverse[0] - data.qfrc_inverse[1])
    expected = result.residual_torque(poses)[:, 0]
    assert np.max(np.abs(np.array(holding) - expected)) <= RELATIVE * np.max(np.abs(expected))


# ---------------------------------------------------------------------- URDF
def test_urdf_anchors_load_back_in_pinocchio_and_yourdfpy(ur5, tmp_path):
    path = tmp_path / "ur5.urdf"
    report = ur5.to_urdf(path)
    assert report.files == [path, sidecar_path(path)]
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    urdf = yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=False)
    original = pin.buildModelFromUrdf(str(robots.robot_urdf("ur5")))
    assert model.nv == original.nv
    for exported, source in zip(model.inertias, original.inertias):  # the anchor links carry no mass
        assert exported.mass == source.mass
        # (Pinocchio merges each fixed link's inertia into its joint body: round-off only)
        np.testing.assert_allclose(exported.lever, source.lever, rtol=0, atol=1e-15)
    for record in ur5.springs:
        for end in ("a", "b"):
            link = anchor_link_name(record["name"], end)
            body = record[end]["body"]
            point = np.array(record[end]["point"])
            frame = data.oMf[model.getFrameId(link)]
            reference = data.oMf[model.getFrameId(body)] if body != "universe" else pin.SE3.Identity()
            assert np.max(np.abs((reference.inverse() * frame).translation - point)) <= 1e-12
            root = urdf.base_link
            transform = urdf.get_transform(link, root if body == "universe" else body)
            assert np.max(np.abs(transform[:3, 3] - point)) <= 1e-12
    sidecar = json.loads(sidecar_path(path).read_text())
    assert [s["name"] for s in sidecar["springs"]] == ["s1", "s2", "s3", "s4"]
    assert sidecar["springs"][0]["stiffness"] == ur5.spring("s1")["stiffness"]


def test_urdf_meshes_keep_working(ur5, tmp_path):
    kept = tmp_path / "kept.urdf"
    ur5.to_urdf(kept)
    assert "package://example-robot-data/" in kept.read_text()
    directories = robots.package_directories()

    def resolve(name):
        relative = name[len("package://") :]
        for directory in directories:
            if (Path(directory) / relative).is_file():
                return str(Path(directory) / relative)
        return name

    urdf = yourdfpy.URDF.load(str(kept), filename_handler=resolve, load_meshes=False, build_scene_graph=False)
    meshes = [
        geometry.geometry.mesh.filename
        for link in urdf.robot.links
        for geometry in link.visuals + link.collisions
        if geometry.geometry.mesh is not None
    ]
    assert meshes and all(Path(resolve(name)).is_file() for name in meshes)
    resolved = tmp_path / "resolved.urdf"
    ur5.to_urdf(resolved, resolve_packages=True)
    text = resolved.read_text()
    assert "package://" not in text
    urdf = yourdfpy.URDF.load(str(resolved), load_meshes=False, build_scene_graph=False)
    assert all(
        Path(geometry.geometry.mesh.filename).is_file()
        for link in urdf.robot.links
        for geometry in link.visuals + link.collisions
        if geometry.geometry.mesh is not None
    )


def test_urdf_round_trip_gives_identical_metrics(two_link, tmp_path):
    path = tmp_path / "two_link.urdf"
    two_link.to_urdf(path)
    mechanism = sb.Mechanism.from_urdf(path, gravity=two_link.problem.mechanism.gravity)
    workspace = sb.Workspace(
        mechanism, two_link.problem.workspace.joint_values, ordered=two_link.problem.workspace.ordered
    )
    springs = springs_from_urdf(path)
    for spring, record in zip(springs, two_link.springs):
        for end in ("a", "b"):
            assert spring.anchors[end].body == record[end]["body"]
    rebuilt = DesignResult(
        DesignProblem(
            mechanism,
            workspace,
            springs,
            objective=two_link.problem.objective.name,
            weights=dict(zip(mechanism.joint_names, two_link.problem.weights)),
        ),
        np.zeros(0),
    )
    before, after = two_link.metrics(), rebuilt.metrics()
    # the same numbers to round-off (a coil's rate G d⁴/(8 D³ n) is folded differently when its
    # values are constants rather than variables); NaN where an objective does not apply
    assert set(after) == set(before)
    for row_after, row_before in zip(after["joints"], before["joints"]):
        for key, value in row_before.items():
            assert row_after[key] == (value if isinstance(value, str) else pytest.approx(value, rel=1e-10, nan_ok=True))
    for name, row in before["objectives"].items():
        assert after["objectives"][name]["after"] == pytest.approx(row["after"], rel=1e-10, abs=1e-12, nan_ok=True)
    np.testing.assert_allclose(rebuilt.evaluation.tau, two_link.evaluation.tau, rtol=0, atol=1e-12)
    np.testing.assert_allclose(rebuilt.evaluation.lengths, two_link.evaluation.lengths, rtol=1e-14, atol=0)


def test_ur5_urdf_round_trip_gives_the_same_metrics(ur5, tmp_path):
    """As above for the UR5. Pinocchio adds each (massless) anchor link's inertia to its body,
    and m·(1/m) ≠ 1 in floating point moves the centres of mass by ~1e-16 m: equal to 1e-12."""
    path = tmp_path / "ur5.urdf"
    ur5.to_urdf(path)
    mechanism = sb.Mechanism.from_urdf(path, gravity=ur5.problem.mechanism.gravity)
    workspace = sb.Workspace(mechanism, ur5.problem.workspace.joint_values, ordered=ur5.problem.workspace.ordered)
    rebuilt = DesignResult(DesignProblem(mechanism, workspace, springs_from_urdf(path)), np.zeros(0))
    before, after = ur5.metrics(), rebuilt.metrics()
    for joint_before, joint_after in zip(before["joints"], after["joints"]):
        for key in ("peak_before", "peak_after", "rms_before", "rms_after"):
            assert joint_after[key] == pytest.approx(joint_before[key], rel=1e-12, abs=1e-13)
    for name, values in before["objectives"].items():
        for key in ("before", "after"):
            assert after["objectives"][name][key] == pytest.approx(values[key], rel=1e-12, nan_ok=True)
    np.testing.assert_array_equal(rebuilt.evaluation.lengths, ur5.evaluation.lengths)


# ---------------------------------------------------------------------- CLI
def test_cli_export_writes_both_files_and_warns(two_link, tmp_path, capsys):
    mechanism = two_link.problem.mechanism
    slack = sb.ExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.1]),
        sb.Anchor("link1", [0.3, 0, 0]),
        "loose",
        stiffness=100.0,
        free_length=0.35,
        keep_tension=False,
    )
    design = tmp_path / "design.json"
    fixed_design(mechanism, [slack], random_inside(mechanism, {"shoulder": (-1.5, 1.5), "elbow": (0, 0)}, n=32)).save(
        design
    )
    urdf, mjcf = tmp_path / "out" / "balanced.urdf", tmp_path / "out" / "balanced.xml"
    # a slack spring that only pulls part of the way is no balancer: it makes the shoulder worse, a failure,
    # so the files are written only with --partial (and the exit status is 3); the law warnings come all the same
    assert main(["export", str(design), "--urdf", str(urdf), "--mjcf", str(mjcf)]) == 3
    assert not urdf.exists() and "[worse_joint]" in capsys.readouterr().err
    assert main(["export", str(design), "--urdf", str(urdf), "--mjcf", str(mjcf), "--partial"]) == 3
    captured = capsys.readouterr()
    assert urdf.is_file() and mjcf.is_file() and sidecar_path(urdf).is_file()
    assert "warning" in captured.err and "'loose'" in captured.err and "slack" in captured.err
    mujoco.MjModel.from_xml_path(str(mjcf))


def test_cli_export_errors_leave_no_file(tmp_path, capsys):
    assert main(["export", str(tmp_path / "missing.json"), "--mjcf", str(tmp_path / "m.xml")]) == 2
    assert capsys.readouterr().err.startswith("springbalance: error: ")
    assert not (tmp_path / "m.xml").exists()
    assert main(["export", str(tmp_path / "missing.json")]) == 2
    # a model MuJoCo cannot build (a floating base): nothing written, URDF included
    text = TWO_LINK.read_text().replace(
        '<joint name="shoulder" type="revolute">', '<joint name="shoulder" type="floating">'
    )
    mechanism = sb.Mechanism.from_urdf(TWO_LINK)
    result = fixed_design(
        mechanism,
        [
            sb.ZeroFreeLengthSpring(
                sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.2, 0, 0]), "s1", stiffness=1.0
            )
        ],
        np.zeros((1, 2)),
    )
    record = result.to_dict()
    record["mechanism"] = {"kind": "urdf_string", "text": text, "gravity": [0, 0, -9.81], "mimic": False}
    design = tmp_path / "floating.json"
    design.write_text(json.dumps(record))
    code = main(["export", str(design), "--urdf", str(tmp_path / "f.urdf"), "--mjcf", str(tmp_path / "f.xml")])
    assert code == 2
    assert not any(tmp_path.glob("f.*"))
    # the URDF is fine but MuJoCo cannot read one of its meshes: neither file is written
    (tmp_path / "broken.stl").write_text("not a mesh")
    text = TWO_LINK.read_text().replace(
        '<geometry><sphere radius="0.03"/></geometry>', '<geometry><mesh filename="broken.stl"/></geometry>'
    )
    broken = tmp_path / "broken.urdf"
    broken.write_text(text)
    result = fixed_design(
        sb.Mechanism.from_urdf(broken),
        [
            sb.ZeroFreeLengthSpring(
                sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.2, 0, 0]), "s1", stiffness=1.0
            )
        ],
        np.zeros((1, 2)),
    )
    result.save(tmp_path / "broken.json")
    capsys.readouterr()
    code = main(
        ["export", str(tmp_path / "broken.json"), "--urdf", str(tmp_path / "g.urdf"), "--mjcf", str(tmp_path / "g.xml")]
    )
    error = capsys.readouterr().err
    assert code == 2 and error.startswith("springbalance: error: ") and error.count("\n") == 1
    assert not any(tmp_path.glob("g.*"))


def test_html_report_links_exported_files(two_link, tmp_path):
    from springbalance.results.html_report import exported_files, report_html

    two_link.to_urdf(tmp_path / "balanced.urdf")
    two_link.to_mjcf(tmp_path / "balanced.xml")
    (tmp_path / "other.xml").write_text("<notmujoco/>")
    assert exported_files(tmp_path) == ["balanced.urdf", "balanced.xml"]
    page = report_html(two_link, scene=None, exports=exported_files(tmp_path))
    assert 'href="balanced.urdf"' in page and 'href="balanced.xml"' in page
    assert "href=" not in report_html(two_link, scene=None, torques=None, histogram=None)


def test_inertia_that_mujoco_rejects_is_balanced_and_reported(tmp_path):
    """An URDF inertia that breaks the triangle inequality (Pinocchio accepts it, MuJoCo does not):
    the export switches balanceinertia on and says so; mass and centre of mass, hence the static
    holding torque, are unchanged."""
    text = TWO_LINK.read_text().replace(
        'ixx="0.0005" ixy="0" ixz="0" iyy="0.042" iyz="0" izz="0.042"',
        'ixx="0.0005" ixy="0" ixz="0" iyy="0.042" iyz="0" izz="0.09"',
    )
    path = tmp_path / "bad_inertia.urdf"
    path.write_text(text)
    mechanism = sb.Mechanism.from_urdf(path, validate=False)  # springbalance refuses it too, unless told not to
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.2, 0, 0]), "s1", stiffness=300.0
    )
    poses = random_inside(mechanism, {"shoulder": (-1.5, 1.5), "elbow": (-2.5, 2.5)}, n=20, seed=3)
    result = fixed_design(mechanism, [spring], poses)
    report = result.to_mjcf(tmp_path / "bad.xml")
    assert any("balanceinertia" in warning for warning in report.warnings)
    assert_same_holding_torque(result, tmp_path / "bad.xml", poses)
