"""The pose slider's numbers (no browser): each pose's joint coordinates, spring forces and residual torques
checked against physics computed here, the JSON the page embeds, and where the slider is put."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from scene_helpers import URDF, model_end_points
from springbalance.cli import main
from springbalance.errors import InputError
from springbalance.viz import scene as viz
from springbalance.viz.pose_data import PoseData, scene_pose_data
from springbalance.viz.pose_paths import parse_poses, scene_poses
from springbalance.viz.pose_slider import DATA_ID, SLIDER_ID, live_page, pose_slider_html


def _scene(design):
    return viz.DesignScene(design, frames_per_joint=8)


def test_pose_numbers_are_the_physics_of_each_pose(design):
    scene = _scene(design)
    data = scene_pose_data(scene)
    mechanism = design.problem.mechanism
    model, pin_data = mechanism.model, mechanism.model.createData()
    q_rad = scene.joint_values
    assert data.size == len(q_rad) == 17  # middle, then 4 frames of each joint's sweep out and back, per joint
    assert [joint["unit"] for joint in data.joints] == ["deg", "deg"]
    # coordinates in degrees
    np.testing.assert_allclose(data.q, np.degrees(q_rad), rtol=1e-5, atol=1e-9)  # 6 significant digits
    # gravity alone: Pinocchio's generalised gravity g(q) [N·m]
    gravity = [pin.computeGeneralizedGravity(model, pin_data, q) for q in mechanism.configurations(q_rad)]
    np.testing.assert_allclose(data.gravity, gravity, rtol=1e-5, atol=1e-9)
    # each spring's tension is Hooke's law on the distance of its ends (ends straight from Pinocchio)
    ends = model_end_points(design, q_rad)
    for column, record in enumerate(design.springs):
        a, b = ends[record["name"]]
        length = np.linalg.norm(b - a, axis=1)
        assert np.all(length > record["free_length"])  # stretched in every pose: F = F0 + k (L - L0)
        force = record.get("initial_tension", 0.0) + record["stiffness"] * (length - record["free_length"])
        np.testing.assert_allclose([row[column] for row in data.force], force, rtol=1e-5)
        np.testing.assert_allclose([row[column] for row in data.length], 1e3 * length, rtol=1e-5)
    # the residual torque is the gradient of the total potential V = V_g + sum V_s: tau_j = dV/dq_j,
    # by central differences of the design's potential at each pose (not its torque formula)
    h = 1e-6
    for k in (0, 2, 6, 10, 14):
        probes = [q_rad[k] + sign * h * np.eye(2)[j] for j in range(2) for sign in (1, -1)]
        potential = design.evaluate_on(sb.Workspace.from_array(mechanism, np.array(probes))).potential
        gradient = [(potential[2 * j] - potential[2 * j + 1]) / (2 * h) for j in range(2)]
        np.testing.assert_allclose(data.tau[k], gradient, rtol=1e-5, atol=1e-6)


def test_pose_data_json_survives_the_page():
    data = PoseData(
        fps=30.0,
        joints=[{"name": "j</script>", "unit": "deg", "torque_unit": "N·m"}],
        springs=[],
        q=[[1.0]],
        tau=[[2.0]],
        gravity=[[3.0]],
        force=[[]],
        length=[[]],
        title="</script><b>",
    )
    text = data.to_json()
    assert "</" not in text  # cannot close the <script> element it sits in
    assert json.loads(text) == data.to_dict()
    fragment = pose_slider_html(data)
    assert fragment.count("</script>") == 2  # the data's element and the script's, nothing from the names


@pytest.mark.parametrize(("joints", "springs", "opened"), [(2, 3, True), (4, 4, True), (6, 4, False), (9, 3, False)])
def test_the_numbers_start_folded_when_they_would_cover_a_large_arm(joints, springs, opened):
    """The table starts open up to OPEN_ROWS (8) joints and springs in all (the two-link demo's 5), folded above
    (the UR5 example's 10, the Panda's 12): a click on its caption opens it."""
    data = PoseData(
        fps=30.0,
        joints=[{"name": f"j{i}", "unit": "deg", "torque_unit": "N·m"} for i in range(joints)],
        springs=[
            {"name": f"s{i}", "type": "extension", "force_unit": "N", "length_unit": "mm"} for i in range(springs)
        ],
        q=[[0.0] * joints],
        tau=[[0.0] * joints],
        gravity=[[0.0] * joints],
        force=[[0.0] * springs],
        length=[[0.0] * springs],
        title="sweep of each joint",
    )
    fragment = pose_slider_html(data)
    assert ("<details open>" in fragment) is opened
    assert fragment.count("<details") == 1 and "<summary>sweep of each joint</summary>" in fragment


def test_static_page_has_the_slider_and_its_data(design):
    scene = _scene(design)
    page = scene.html(autoplay=False)
    slider = re.search(rf'<input id="{SLIDER_ID}" type="range" min="1" max="(\d+)"', page)
    assert slider is not None and int(slider.group(1)) == scene.size
    embedded = re.search(rf'<script type="application/json" id="{DATA_ID}">(.*?)</script>', page, re.S)
    assert embedded is not None
    data = json.loads(embedded.group(1))
    assert data == json.loads(scene_pose_data(scene).to_json())
    assert data["fps"] == scene.fps and len(data["tau"]) == scene.size
    assert data["title"] == "sweep of each joint"
    # a page without animation has nothing to scrub
    assert SLIDER_ID not in scene.html(animate=False)


def test_live_page_loads_meshcat_from_its_server(design):
    scene = _scene(design)
    page = live_page(scene_pose_data(scene), scene.legend_html())
    assert '<script src="/static/main.min.js"></script>' in page  # same origin: the loopback server
    assert "viewer.connect()" in page and SLIDER_ID in page and "springbalance-legend" in page
    assert "http" not in page.split(DATA_ID)[0]  # no address elsewhere: nothing from the network


def test_prismatic_coordinates_in_mm_and_torsional_springs_in_degrees():
    urdf = """<robot name="slide"><link name="base"/><link name="carriage">
      <inertial><mass value="2"/><origin xyz="0 0 0"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="arm"><inertial><mass value="1"/><origin xyz="0.2 0 0"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="lift" type="prismatic"><parent link="base"/><child link="carriage"/><axis xyz="0 0 1"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint>
      <joint name="hinge" type="revolute"><parent link="carriage"/><child link="arm"/><axis xyz="0 -1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"""
    mechanism = sb.Mechanism.from_urdf_string(urdf)
    workspace = sb.Workspace.from_array(mechanism, [[0.1, 0.2], [0.3, -0.4]])
    springs = [sb.TorsionalSpring("hinge", name="coil", stiffness=2.0, neutral_angle=0.0)]
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="rms")
    design = sb.DesignResult(problem, np.zeros(0))
    data = scene_pose_data(viz.DesignScene(design, workspace.joint_values))
    assert [joint["unit"] for joint in data.joints] == ["mm", "deg"]
    assert [joint["torque_unit"] for joint in data.joints] == ["N", "N·m"]
    np.testing.assert_allclose(data.q, [[100.0, math.degrees(0.2)], [300.0, math.degrees(-0.4)]], rtol=1e-5)
    assert data.springs == [{"name": "coil", "type": "torsional", "force_unit": "N·m", "length_unit": "deg"}]
    # a torsional spring's torque is k (q - q0) = 2 N·m/rad × (0.2 rad, -0.4 rad)
    np.testing.assert_allclose([row[0] for row in data.force], [0.4, -0.8], rtol=1e-5)
    np.testing.assert_allclose([row[0] for row in data.length], [math.degrees(0.2), math.degrees(-0.4)], rtol=1e-5)
    # the lift carries both bodies: gravity alone on it is (2 + 1) kg · 9.81 m/s² [N], whatever the hinge does
    np.testing.assert_allclose([row[0] for row in data.gravity], [3 * 9.81] * 2, rtol=1e-3)


# ---------------------------------------------------------------------- which poses: sweep, workspace, worst
@pytest.mark.parametrize(
    "spec, expected",
    [
        ("sweep", ("sweep", None)),
        ("workspace", ("workspace", None)),
        ("worst", ("worst", None)),
        ("worst:3", ("worst", 3)),
    ],
)
def test_parse_poses(spec, expected):
    assert parse_poses(spec) == expected


@pytest.mark.parametrize("spec", ["all", "worst:0", "worst:x", "worst:-2", "sweep:3", ""])
def test_bad_poses_name_the_value(spec):
    with pytest.raises(InputError, match=re.escape(repr(spec))):
        parse_poses(spec)


def test_worst_poses_have_the_largest_residual_torque(design):
    """The residual torque is the gradient of the total potential (checked above): the worst poses' weighted norms,
    from central differences of the potential at every workspace sample, are the largest, in decreasing order."""
    mechanism, samples = design.problem.mechanism, design.problem.workspace.joint_values
    h = 1e-6
    probes = np.array([q + sign * h * np.eye(2)[j] for q in samples for j in range(2) for sign in (1, -1)])
    potential = design.evaluate_on(sb.Workspace.from_array(mechanism, probes)).potential.reshape(len(samples), 2, 2)
    gradient = (potential[:, :, 0] - potential[:, :, 1]) / (2 * h)  # N×2 [N·m]
    norm = np.linalg.norm(gradient * design.problem.weights, axis=1)
    joint_values, title = scene_poses(design, "worst:5")
    chosen = [int(np.flatnonzero(np.all(samples == row, axis=1))[0]) for row in joint_values]
    assert len(chosen) == 5 and title == "the 5 worst poses (largest residual torque first)"
    assert np.all(np.diff(norm[chosen]) <= 1e-6)  # worst first
    assert norm[chosen].min() >= np.delete(norm, chosen).max() - 1e-6  # none left out is worse
    # the whole workspace, in its order; a scene made from either
    joint_values, title = scene_poses(design, "workspace")
    np.testing.assert_array_equal(joint_values, samples)
    scene = viz.DesignScene(design, poses="worst:4")
    assert scene.size == 4 and scene_pose_data(scene).title == "the 4 worst poses (largest residual torque first)"


def test_report_and_view_take_poses(design_file, tmp_path, capsys):
    out = tmp_path / "report"
    assert main(["report", str(design_file), "--out", str(out), "--poses", "worst:3"]) in (0, 3)
    page = (out / "scene.html").read_text()
    assert re.search(rf'<input id="{SLIDER_ID}" type="range" min="1" max="3"', page)
    assert "the 3 worst poses" in page
    capsys.readouterr()
    for command in (["report", str(design_file), "--out", str(tmp_path / "r2")], ["view", str(design_file)]):
        assert main([*command, "--poses", "worst:0"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("springbalance: error: poses 'worst:0'"), err


def test_a_directed_force_shows_its_stroke_in_mm_and_its_force_in_n():
    """A constant 50 N upward on link1 at (0.1, 0, 0): its stroke is the anchor's height s = u·p = 0.1 sin θ [m]
    (shoulder θ, lifting link1 from +x towards +z; docs/model.md §3.11), shown in mm, its force 50 N."""
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    force = sb.DirectedForce(sb.Anchor("link1", (0.1, 0.0, 0.0)), "lift", direction=(0, 0, 1), force=50.0)
    angles = np.radians([-30.0, 0.0, 45.0])
    path = np.column_stack([angles, np.zeros(3)])
    design = sb.DesignResult(sb.DesignProblem(mechanism, sb.Workspace.from_array(mechanism, path), [force]), [])
    data = scene_pose_data(viz.DesignScene(design, path)).to_dict()
    assert data["springs"] == [{"name": "lift", "type": "directed_force", "force_unit": "N", "length_unit": "mm"}]
    np.testing.assert_allclose(np.array(data["length"])[:, 0], 1e3 * 0.1 * np.sin(angles), atol=1e-3)
    np.testing.assert_allclose(np.array(data["force"])[:, 0], 50.0)
