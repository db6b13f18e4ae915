"""Routed springs (docs/model.md §3.9): a spring on one body pulling a cable over pulleys.

The checks are independent of the library's own path model where they can be:

- exact balance is the residual torque of the design against the unbalanced gravity torque;
- MuJoCo's inverse dynamics (``mj_inverse``) of the exported model, whose spatial tendon runs
  through the same sites, gives the holding torque on its own;
- the torque of a routed spring equals the finite-difference derivative of the total potential;
  for guide points (radius 0) that potential is computed here from Pinocchio alone, and the
  length over a wrapping pulley is checked against configurations whose length is known in
  closed form (quarter and half wraps).
"""

from __future__ import annotations

import math
from pathlib import Path

import casadi as ca
import mujoco
import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from mujoco_helpers import mujoco_holding_torque, random_inside
from physics_helpers import ReferencePotential
from springbalance.cli import main
from springbalance.design.problem import DesignProblem
from springbalance.results.result import DesignResult
from springbalance.springs.routing import path_length

ROOT = Path(__file__).resolve().parents[2]
R2 = ROOT / "urdf" / "single_link_r2.urdf"
TWO_LINK = ROOT / "urdf" / "two_link_planar.urdf"
EXACT = 1e-6  # residual peak / unbalanced peak of an exact design (must-hold)
F = sb.Free


def routed_zfl(name, spring_end, guide, cable_end, radius=0.0):
    """A zero-free-length law on a routed path: the spring from ``spring_end`` towards ``guide``, the
    cable on to ``cable_end`` (each a ``(body, point or Free)`` pair)."""
    return sb.ZeroFreeLengthSpring(
        sb.Anchor(*spring_end),
        sb.Anchor(*cable_end),
        name,
        via=[sb.Pulley(sb.Anchor(*guide), radius)],
        cable_length=F(0, 3),
        stiffness=F(0, 5000),
    )


# ---------------------------------------------------------------------- must-hold 1: one link
@pytest.fixture(scope="module")
def single_link():
    """R2's link (1 kg, centre of mass 0.25 m, g = 9.8) and one helical extension coil on it: its body
    from 0.35 m behind the pivot to a guide point 0.04 m along the link, the cable from there to a
    ground point 0.1 m above the pivot (so the cable's free part is 0.06 … 0.14 m long)."""
    mechanism = sb.Mechanism.from_urdf(R2, gravity=9.8)
    workspace = sb.Workspace.sobol(mechanism, n=256, seed=0)
    coil = sb.HelicalExtensionSpring(
        sb.Anchor("link1", [-0.35, 0, 0]),
        sb.Anchor("ground", [0, 0, 0.1]),
        "s1",
        via=[sb.Pulley(sb.Anchor("link1", [0.04, 0, 0]))],
        cable_length=F(0, 1),
    )
    return sb.solve(DesignProblem(mechanism, workspace, [coil]), starts=4, progress=False)


def test_one_routed_coil_balances_r2_exactly_and_is_buildable(single_link):
    balance = single_link.exact_balance()
    assert balance["relative_residual"] < EXACT
    record = single_link.spring("s1")
    sheet = record["helical"]
    assert sheet["buildable"], sheet["reasons"]
    tensions = single_link.evaluation.tensions[:, 0]
    assert np.all(tensions > 0)  # the cable never goes slack
    # the coil fits on its segment (0.39 m from its end to the guide point) at every sample
    assert np.max(single_link.evaluation.lengths[:, 0]) <= 0.39 + 1e-9
    # and it is the spring the law says: F = F_i + k (L - l0) with L = path - cable
    lengths = single_link.evaluation.lengths[:, 0]
    np.testing.assert_allclose(
        tensions, record["initial_tension"] + record["stiffness"] * (lengths - record["free_length"]), rtol=1e-9
    )
    assert "Exactly balanced" in single_link.table()


# ---------------------------------------------------------------------- must-hold 2: two links
@pytest.fixture(scope="module")
def two_link():
    """Three routed zero-free-length springs on the two-link arm: on a mast above the shoulder to link 1
    and to link 2 (spanning both joints), and along link 1 with the cable over a guide point at the
    elbow to link 2."""
    mechanism = sb.Mechanism.from_urdf(TWO_LINK)
    workspace = sb.Workspace.sobol(mechanism, n=256, seed=0)
    springs = [
        routed_zfl(
            "s1",
            ("base", [0, 0, 1.0]),
            ("base", F([-0.05, 0, 0.05], [0.05, 0, 0.3], init=[0, 0, 0.2])),
            ("link1", F([0.05, 0, -0.05], [0.5, 0, 0.05], init=[0.3, 0, 0])),
        ),
        routed_zfl(
            "s2",
            ("base", [0.05, 0, 1.6]),
            ("base", F([-0.05, 0, 0.05], [0.05, 0, 0.3], init=[0, 0, 0.15])),
            ("link2", F([0.02, 0, -0.05], [0.4, 0, 0.05], init=[0.2, 0, 0])),
        ),
        routed_zfl(
            "s3",
            ("link1", [-0.3, 0, 0]),
            ("link1", F([0.35, 0, -0.1], [0.6, 0, 0.1], init=[0.45, 0, 0.05])),
            ("link2", F([0.02, 0, -0.05], [0.4, 0, 0.05], init=[0.1, 0, 0])),
        ),
    ]
    return sb.solve(DesignProblem(mechanism, workspace, springs), starts=8, progress=False)


def test_routed_springs_alone_balance_the_two_link_arm_exactly(two_link):
    balance = two_link.exact_balance()
    assert balance["relative_residual"] < EXACT
    assert balance["exact"]  # the report's own verdict
    assert "Exactly balanced" in two_link.table()
    # the forearm spring's cable runs over the guide point near the elbow (on link 1) to link 2
    elbow_guide = np.array(two_link.spring("s3")["via1"]["point"])
    assert two_link.spring("s3")["via1"]["body"] == "link1" and abs(elbow_guide[0] - 0.5) <= 0.1
    # every spring fits on its segment and never pushes
    assert np.all(two_link.evaluation.tensions >= -1e-9)


def test_saved_routed_design_loads_back_with_the_same_residual(two_link, tmp_path):
    path = two_link.save(tmp_path / "routed.json")
    loaded = DesignResult.load(path)
    assert [spring.via[0].anchor.body for spring in loaded.problem.springs] == ["base", "base", "link1"]
    np.testing.assert_allclose(loaded.evaluation.tau, two_link.evaluation.tau, atol=1e-12)
    np.testing.assert_allclose(
        loaded.residual_torque(two_link.problem.workspace.joint_values), two_link.evaluation.tau, atol=1e-12
    )
    # the exported URDF carries a link at every point of each path, and its springs load back
    from springbalance.io.urdf import springs_from_urdf

    two_link.to_urdf(tmp_path / "routed.urdf")
    springs = springs_from_urdf(tmp_path / "routed.urdf")
    assert [len(spring.anchors) for spring in springs] == [3, 3, 3]
    again = DesignResult(DesignProblem(two_link.problem.mechanism, two_link.problem.workspace, springs), np.zeros(0))
    np.testing.assert_allclose(again.evaluation.tau, two_link.evaluation.tau, atol=1e-9)


# ---------------------------------------------------------------------- must-hold 3: MuJoCo
def _mujoco_check(result, tmp_path, name):
    mechanism = result.problem.mechanism
    ranges = {joint.name: (joint.lower, joint.upper) for joint in mechanism.joints}
    poses = random_inside(mechanism, ranges, n=100, seed=4)
    result.to_mjcf(tmp_path / f"{name}.xml")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / f"{name}.xml"))
    assert model.ntendon == len(result.problem.springs)
    expected = result.residual_torque(poses)
    measured = mujoco_holding_torque(tmp_path / f"{name}.xml", mechanism, poses)
    unbalanced = float(np.max(np.abs(result.problem.workspace.kinematics().gravity_torque)))
    assert np.max(np.abs(measured - expected)) <= 1e-9 * unbalanced
    return poses


@pytest.mark.parametrize("case", ["single_link", "two_link"])
def test_mujoco_tendons_over_the_same_sites_hold_the_arm_alike(case, request, tmp_path):
    result = request.getfixturevalue(case)
    _mujoco_check(result, tmp_path, case)
    # the same paths with other stiffnesses and cables: a residual far from zero, still equal in MuJoCo
    problem = result.problem
    x = np.array(result.x, dtype=float)
    for i, name in enumerate(problem.variables.names):
        if name.endswith("cable_length"):
            x[i] *= 0.9
        if name.endswith("stiffness") or name.endswith("active_coils"):
            x[i] *= 1.3
    detuned = sb.DesignResult(problem, x)
    assert np.max(np.abs(detuned.evaluation.tau)) > 0.05 * np.max(np.abs(problem.workspace.kinematics().gravity_torque))
    poses = _mujoco_check(detuned, tmp_path, f"{case}_detuned")
    expected = detuned.residual_torque(poses)
    assert np.max(np.abs(expected)) > 0.05 * np.max(np.abs(problem.workspace.kinematics().gravity_torque))


def test_wrapping_pulleys_export_with_their_length_error_stated(tmp_path):
    """MuJoCo cannot force a tendon round the outside of a pulley: the export runs it through the
    centres, draws the pulleys, and says how far that is from the wrapped cable."""
    mechanism = sb.Mechanism.from_urdf(TWO_LINK)
    poses = np.column_stack([np.linspace(-1.2, 1.2, 25), np.linspace(-2.0, 2.0, 25)])
    via = [sb.Pulley(sb.Anchor(body, point), radius) for body, point, radius in PATHS[2]]
    spring = sb.ExtensionSpring(
        sb.Anchor("base", [0.1, 0.05, 1.2]),
        sb.Anchor("link2", [0.35, 0.0, -0.03]),
        "r",
        via=via,
        cable_length=0.4,
        stiffness=300.0,
        free_length=0.2,
        keep_tension=False,
    )
    result = DesignResult(
        DesignProblem(mechanism, sb.Workspace.from_array(mechanism, poses, ordered=False), [spring]), np.zeros(0)
    )
    report = result.to_mjcf(tmp_path / "wrap.xml")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "wrap.xml"))
    assert model.ntendon == 1 and model.ngeom >= 2
    warning = next(text for text in report.warnings if "wrapping pulleys" in text)
    stated = float(warning.split("by up to ")[1].split(" m")[0])
    # the same path through the centres (radius 0) is what MuJoCo measures; the stated error is the largest gap
    centres = [sb.Pulley(pulley.anchor, 0.0) for pulley in via]
    straight = sb.ExtensionSpring(
        spring.a, spring.b, "r", via=centres, cable_length=0.4, stiffness=300.0, free_length=0.2, keep_tension=False
    )
    through = DesignResult(
        DesignProblem(mechanism, sb.Workspace.from_array(mechanism, poses, ordered=False), [straight]), np.zeros(0)
    )
    gap = np.max(np.abs(result.evaluation.lengths - through.evaluation.lengths))
    assert stated == pytest.approx(gap, rel=1e-2)
    data = mujoco.MjData(model)
    for row, length in zip(poses, through.evaluation.lengths[:, 0]):
        data.qpos[:] = row
        mujoco.mj_forward(model, data)
        assert data.ten_length[0] == pytest.approx(length + 0.4, abs=1e-9)


# ---------------------------------------------------------------------- must-hold 4: physics
def _torque_and_potential_derivative(springs, poses, step=1e-4):
    """The model's torque at ``poses``, and the 4th-order central difference of its total potential."""
    mechanism = sb.Mechanism.from_urdf(TWO_LINK)
    nv = mechanism.nv
    shifted = [poses]
    for j in range(nv):
        for h in (2 * step, step, -step, -2 * step):
            moved = poses.copy()
            moved[:, j] += h
            shifted.append(moved)
    workspace = sb.Workspace.from_array(mechanism, np.vstack(shifted), ordered=False)
    evaluation = DesignResult(DesignProblem(mechanism, workspace, springs), np.zeros(0)).evaluation
    n = len(poses)
    torque = evaluation.tau[:n]
    potential = evaluation.potential[n:].reshape(nv, 4, n)
    derivative = ((-potential[:, 0] + 8 * potential[:, 1] - 8 * potential[:, 2] + potential[:, 3]) / (12 * step)).T
    return torque, derivative, mechanism, evaluation.lengths[:n]


PATHS = {
    1: [("link1", [0.45, -0.03, 0.05], 0.02)],
    2: [("base", [0.0, 0.02, 0.3], 0.02), ("link1", [0.45, -0.03, 0.05], 0.015)],
    3: [("base", [0.0, 0.02, 0.3], 0.02), ("link1", [0.45, -0.03, 0.05], 0.015), ("link2", [0.1, 0.02, 0.06], 0.01)],
}


@pytest.mark.parametrize("pulleys", [1, 2, 3])
@pytest.mark.parametrize("wrapping", [False, True])
def test_torque_is_the_derivative_of_the_potential(pulleys, wrapping):
    """A 3-D path from a ground mast over 1, 2 or 3 pulleys (guide points, or wrapping pulleys of
    10–20 mm) to link 2, with an extension law, initial tension and the spring's own mass."""
    via = [sb.Pulley(sb.Anchor(body, point), radius if wrapping else 0.0) for body, point, radius in PATHS[pulleys]]
    spring = sb.ExtensionSpring(
        sb.Anchor("base", [0.1, 0.05, 1.2]),
        sb.Anchor("link2", [0.35, 0.0, -0.03]),
        "r",
        via=via,
        cable_length=0.4,
        stiffness=300.0,
        free_length=0.2,
        initial_tension=12.0,
        keep_tension=False,
        mass=0.2,
    )
    rng = np.random.default_rng(pulleys)
    poses = np.column_stack([rng.uniform(-1.2, 1.2, 20), rng.uniform(-2.2, 2.2, 20)])
    torque, derivative, mechanism, lengths = _torque_and_potential_derivative([spring], poses)
    assert np.max(np.abs(torque - derivative)) <= 1e-6 * np.max(np.abs(torque))
    if not wrapping:
        # guide points: the potential from Pinocchio alone, path = sum of the segments
        model = mechanism.model
        data = model.createData()
        points = (
            [("base", [0.1, 0.05, 1.2])]
            + [(body, point) for body, point, _ in PATHS[pulleys]]
            + [("link2", [0.35, 0.0, -0.03])]
        )
        for row, q in zip(lengths, poses):
            pin.framesForwardKinematics(model, data, mechanism.configurations(q[None])[0])
            world = [data.oMf[model.getFrameId(body)].act(np.array(point, dtype=float)) for body, point in points]
            path = sum(np.linalg.norm(b - a) for a, b in zip(world, world[1:]))
            assert row[0] == pytest.approx(path - 0.4, abs=1e-12)


def test_reference_potential_agrees_on_a_straight_cable():
    """A routed spring with no pulley is a spring in series with a cable: L = |x_b - x_a| - cable."""
    spring = sb.ExtensionSpring(
        sb.Anchor("base", [0.0, 0.0, 0.4]),
        sb.Anchor("link1", [0.3, 0.0, 0.0]),
        "r",
        cable_length=0.1,
        stiffness=200.0,
        free_length=0.05,
    )
    plain = sb.ExtensionSpring(
        sb.Anchor("base", [0.0, 0.0, 0.4]), sb.Anchor("link1", [0.3, 0.0, 0.0]), "p", stiffness=200.0, free_length=0.15
    )
    poses = np.column_stack([np.linspace(-1.0, 1.0, 9), np.zeros(9)])
    torque, derivative, mechanism, _ = _torque_and_potential_derivative([spring], poses)
    reference, *_ = _torque_and_potential_derivative([plain], poses)
    np.testing.assert_allclose(torque, reference, atol=1e-12)
    from physics_helpers import RefSpring

    potential = ReferencePotential(mechanism.model, [RefSpring("base", (0, 0, 0.4), "link1", (0.3, 0, 0), 200.0, 0.15)])
    for q, tau in zip(poses, torque):
        np.testing.assert_allclose(tau, potential.torque(mechanism.configurations(q[None])[0]), atol=1e-7)


@pytest.mark.parametrize("r, d", [(0.01, 0.3), (0.05, 0.2)])
def test_wrap_lengths_in_closed_form(r, d):
    """Quarter wrap: from (-d, r) along y = r, over the pulley at the origin, down x = r to (r, -d):
    2 d + π r / 2. Half wrap: up from (-r, -d), over the top, down to (r, -d): 2 d + π r."""

    def length(a, b):
        points = [ca.DM(np.array(a, dtype=float)), ca.DM.zeros(3, 1), ca.DM(np.array(b, dtype=float))]
        value, _ = path_length(points, [0.0, r, 0.0])
        return float(ca.DM(value))

    assert length([-d, r, 0], [r, -d, 0]) == pytest.approx(2 * d + math.pi * r / 2, abs=1e-12)
    assert length([-r, -d, 0], [r, -d, 0]) == pytest.approx(2 * d + math.pi * r, abs=1e-12)
    # the plane of the wrap follows the points (a swivelling pulley): the same wrap turned about x
    turn = np.array([[1, 0, 0], [0, 0.6, -0.8], [0, 0.8, 0.6]])
    assert length(turn @ [-d, r, 0], turn @ [r, -d, 0]) == pytest.approx(2 * d + math.pi * r / 2, abs=1e-12)


# ---------------------------------------------------------------------- config, scene and bad input
def _config(tmp_path, path_text, cable="{lower: 0.0, upper: 1.0}", law="{helical: {material: music_wire}}"):
    config = tmp_path / "routed.yaml"
    config.write_text(f"""
mechanism: {{urdf: {R2}, gravity: 9.8}}
workspace: {{kind: sobol, n: 64}}
springs:
  - name: s1
    type: routed
    path: {path_text}
    spring: {law}
    cable_length: {cable}
""")
    return config


GOOD_PATH = (
    "[{body: link1, point: [-0.35, 0, 0]}, {body: link1, point: [0.04, 0, 0]}, {body: ground, point: [0, 0, 0.1]}]"
)


def test_example_config_designs_saves_reports_and_draws(tmp_path, capsys):
    config = ROOT / "examples" / "routed_link.yaml"  # the routed spring of docs/guides/routed-springs.md
    out = tmp_path / "design.json"
    assert main(["design", str(config), "--out", str(out), "--starts", "2"]) == 0
    text = capsys.readouterr().out
    assert "Exactly balanced" in text and "via1:" in text and "BUILDABLE" in text
    loaded = DesignResult.load(out)
    spring = loaded.problem.springs[0]
    assert spring.routed and spring.to_dict()["type"] == "routed"
    from springbalance.viz.scene import DesignScene

    scene = DesignScene(loaded, frames_per_joint=8)
    track = scene.springs[0]
    assert track.cable is not None and track.cable.shape[1:] == (3, 3)
    # the helix lies on the first segment, as long as the spring, and the cable starts where it ends
    np.testing.assert_allclose(
        np.linalg.norm(track.ends - track.starts, axis=1), scene.evaluation.lengths[:, 0], atol=1e-12
    )
    np.testing.assert_allclose(track.cable[:, 0], track.ends, atol=1e-12)
    np.testing.assert_allclose(track.cable[:, -1], track.points_by_end()["b"], atol=1e-12)
    # what meshcat receives: each cable segment, a unit cylinder along y, spans its two points in every frame
    import meshcat
    import umsgpack
    from meshcat.servers.tree import walk

    from scene_helpers import track_keys
    from springbalance.viz.recorder import SceneRecorder
    from springbalance.viz.scene import ROOT as SCENE_ROOT

    recorder = SceneRecorder()
    scene.draw(meshcat.Visualizer(window=recorder))
    animation = next(umsgpack.unpackb(node.animation) for node in walk(recorder.tree) if node.animation is not None)
    clips = {item["path"]: item["clip"] for item in animation["animations"]}
    for segment in range(2):
        clip = clips[f"/meshcat/{SCENE_ROOT}/cables/s1/segment{segment}"]
        tracks = {track["name"]: track_keys(track) for track in clip["tracks"]}
        for frame in range(scene.size):
            x, y, z, w = tracks[".quaternion"][frame]
            rotation = np.array(
                [
                    [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
                ]
            )
            scale, position = np.array(tracks[".scale"][frame]), np.array(tracks[".position"][frame])
            ends = sorted(
                [position + rotation @ (scale * [0, -0.5, 0]), position + rotation @ (scale * [0, 0.5, 0])],
                key=lambda p: np.linalg.norm(p - track.cable[frame, segment]),
            )
            # key frames are float32 (scene_helpers.FLOAT32_ATOL)
            np.testing.assert_allclose(ends[0], track.cable[frame, segment], atol=1e-6)
            np.testing.assert_allclose(ends[1], track.cable[frame, segment + 1], atol=1e-6)


@pytest.mark.parametrize(
    "path_text, cable, expected",
    [
        ("[{body: link1, point: [-0.35, 0, 0]}]", "0.1", "at least two points"),
        (
            "[{body: link1, point: [-0.35, 0, 0]}, {body: link1, point: [-0.35, 0, 0]}, {body: ground, point: [0, 0, 0.1]}]",
            "0.1",
            "coincide on body 'link1'",
        ),
        (
            "[{body: link1, point: [-0.35, 0, 0]}, {body: link1, point: [0.04, 0, 0], pulley: {radius: -0.01}}, "
            "{body: ground, point: [0, 0, 0.1]}]",
            "0.1",
            "path[1].pulley.radius",
        ),
        (GOOD_PATH, "2.0", "would be slack everywhere"),
    ],
)
def test_bad_routed_springs_get_one_line_naming_the_culprit(tmp_path, capsys, path_text, cable, expected):
    config = _config(tmp_path, path_text, cable)
    out = tmp_path / "design.json"
    assert main(["design", str(config), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert expected in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert "s1" in err or "springs[0]" in err
    assert not out.exists()
