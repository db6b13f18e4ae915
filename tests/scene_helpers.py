"""Designs for the scene, plot and report tests: built without solving, so they are fast.

``two_link_design()`` is the two-link planar arm of urdf/two_link_planar.urdf (link1 blue,
RGBA 0.2 0.3 0.8) with two extension springs whose values are the middles of their
bounds (the design vector is the problem's first guess):

- ``shoulder``: ground point (0, 0, 0.15) to a point free on a segment of link1, stiff, so
  its tension is high (dark raspberry on the colour scale);
- ``forearm``: a point free in a box of link1 to a point of link2, soft, so its tension
  stays low (yellow).

And what the scene tests share: the springs' ends straight from Pinocchio, a scene recorded in memory
and its animation clips, Chromium (or a skip), and the "crossing" spring that link2 passes through.
"""

from __future__ import annotations

import colorsys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import umsgpack

import springbalance as sb
from springbalance.viz import browser
from springbalance.viz import scene as viz
from springbalance.viz.camera import SCENE_FOV
from springbalance.viz.meshcat_import import import_meshcat
from springbalance.viz.recorder import SceneRecorder

meshcat = import_meshcat()  # silences meshcat's import-time deprecation warning
from meshcat.servers.tree import walk  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
URDF = ROOT / "urdf"
LINK1_RGB = (0.2, 0.3, 0.8)


def two_link_design(n: int = 7, floor: float | None = None) -> sb.DesignResult:
    """The two-link arm with a ground spring and an elbow spring (``floor`` [m]: the mechanism's floor)."""
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf", floor=floor)
    workspace = sb.Workspace.grid(mechanism, n, ranges={"shoulder": [-80, 80], "elbow": [-100, 100]}, degrees=True)
    springs = [
        sb.ExtensionSpring(
            sb.Anchor("universe", (0.0, 0.0, 0.15)),
            sb.Anchor("link1", sb.Segment((0.1, 0, 0), (0.45, 0, 0), lower=0.4, upper=0.8)),
            name="shoulder",
            stiffness=sb.Free(600, 800),
            free_length=0.05,
        ),
        sb.ExtensionSpring(
            sb.Anchor("link1", sb.Free([0.05, 0, 0.03], [0.2, 0, 0.08])),
            sb.Anchor("link2", (0.25, 0, 0)),
            name="forearm",
            stiffness=20.0,
            free_length=0.05,
            keep_tension=False,
        ),
    ]
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="rms")
    return sb.DesignResult(problem, np.array(problem.variables.start))


def ur5_design(n: int = 16) -> sb.DesignResult:
    """UR5 (example-robot-data meshes) with two springs anchored off-axis, random samples."""
    mechanism = sb.Mechanism.from_robot("ur5")
    workspace = sb.Workspace.random(mechanism, n, seed=3)
    springs = [
        sb.ExtensionSpring(
            sb.Anchor("universe", (0.05, 0.1, 0.4)),
            sb.Anchor("upper_arm_link", (0.02, 0.05, 0.2)),
            name="s1",
            stiffness=1500.0,
            free_length=0.05,
            keep_tension=False,
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("shoulder_link", sb.Free([-0.1, -0.1, 0.0], [0.1, 0.1, 0.1])),
            sb.Anchor("forearm_link", (0.1, 0.0, 0.02)),
            name="s2",
            stiffness=800.0,
        ),
    ]
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="rms")
    return sb.DesignResult(problem, np.array(problem.variables.start))


# ---------------------------------------------------------------------- what the scene tests share
def model_end_points(result, joint_values):
    """World positions of each spring's ends straight from Pinocchio (not from the scene code)."""
    mechanism = result.problem.mechanism
    model = mechanism.model
    data = model.createData()
    ends = {record["name"]: ([], []) for record in result.springs}
    for q in mechanism.configurations(joint_values):
        pin.framesForwardKinematics(model, data, q)
        for record in result.springs:
            for slot, end in enumerate(("a", "b")):
                frame = data.oMf[mechanism.frame_id(record[end]["body"])]
                ends[record["name"]][slot].append(frame.act(np.array(record[end]["point"])))
    return {name: (np.array(a), np.array(b)) for name, (a, b) in ends.items()}


def recorded_scene(result, path):
    recorder = SceneRecorder()
    visualizer = meshcat.Visualizer(window=recorder)
    scene = viz.DesignScene(result, path)
    scene.draw(visualizer)
    return scene, recorder


def track_keys(track):
    """The value of each key frame of a lowered animation track, frame by frame: the scene sends
    ``times`` and flat ``values`` as float32 arrays (msgpack Float32Array extensions); meshcat's own
    tracks have ``keys``."""
    if "keys" in track:
        return [key["value"] for key in track["keys"]]
    times = np.frombuffer(track["times"].data, dtype=np.float32)
    np.testing.assert_array_equal(times, np.arange(len(times)))  # one key per frame, in order
    values = np.frombuffer(track["values"].data, dtype=np.float32).astype(float)
    return values.reshape(len(times), -1).tolist()


#: what float32 key frames keep of a value of about 1 [m or 1]: 2^-24 relative, with margin
FLOAT32_ATOL = 1e-6


def animation_clips(recorder):
    animation = next(umsgpack.unpackb(node.animation) for node in walk(recorder.tree) if node.animation is not None)
    return {
        item["path"]: {track["name"]: track_keys(track) for track in item["clip"]["tracks"]}
        for item in animation["animations"]
    }


def record_scene(scene):
    recorder = SceneRecorder()
    scene.draw(meshcat.Visualizer(window=recorder))
    return recorder


def require_chromium():
    if browser.find_chromium() is None:
        pytest.skip(
            "Chromium is not installed (Debian package `chromium`; `make chromium` installs it as root); "
            "run `make demo-check` where it is"
        )


def hue_distance(rgb_1, rgb_2) -> float:
    h1, h2 = (360 * colorsys.rgb_to_hsv(*rgb)[0] for rgb in (rgb_1, rgb_2))
    return abs((h1 - h2 + 180) % 360 - 180)


# urdf/two_link_planar_collision.urdf (see its header): both joints turn about (0, -1, 0), so a
# positive angle lifts a link from +x towards +z; link1 runs 0.5 m along x from the shoulder (the
# origin), link2's collision box is 0.4 × 0.03 × 0.03 m, centred 0.2 m along link2 from the elbow.
# "crossing" runs from the ground point P = (0.6, 0, 0.25) to S = (0.4, 0, 0) on link1; with the
# shoulder at 0 the elbow sits at E = (0.5, 0, 0) and link2 points along (cos e, 0, sin e).
COLLISION_URDF = URDF / "two_link_planar_collision.urdf"
CROSSING_P, CROSSING_S, ELBOW = np.array([0.6, 0.0, 0.25]), np.array([0.4, 0.0, 0.0]), np.array([0.5, 0.0, 0.0])
LINK2_LENGTH, LINK2_HALF_WIDTH = 0.4, 0.015  # [m] of link2's box
CAPSULE_RADIUS = 0.01  # [m] of a spring without a spec sheet
MARGIN = 0.02  # [m]


def fixed_design(urdf, springs, path, **options):
    """A design of fixed springs (no free variable) whose workspace is ``path`` (N×2) [rad]."""
    mechanism = sb.Mechanism.from_urdf(urdf)
    problem = sb.DesignProblem(mechanism, sb.Workspace.from_array(mechanism, path), springs, **options)
    return sb.DesignResult(problem, np.zeros(0))


def crossing_spring():
    return sb.ExtensionSpring(
        sb.Anchor("universe", tuple(CROSSING_P)),
        sb.Anchor("link1", tuple(CROSSING_S)),
        name="crossing",
        stiffness=300.0,
        free_length=0.05,
    )


def elbow_path(degrees):
    elbow = np.radians(degrees)
    return np.column_stack([np.zeros_like(elbow), elbow])


def project(scene, points, window=browser.WINDOW):
    """Pixel coordinates (K×2: right, down) [px] of world ``points`` (K×3) [m] in a ``window`` (width,
    height) view of the scene: meshcat's perspective camera (the vertical field of view the scene gives it,
    45°, the window's aspect, world z up) at ``scene.camera_position`` looking at ``scene.camera_target``."""
    width, height = window
    camera, target = np.asarray(scene.camera_position), np.asarray(scene.camera_target)
    forward = (target - camera) / np.linalg.norm(target - camera)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    relative = np.asarray(points, dtype=float) - camera
    depth = relative @ forward
    assert np.all(depth > 0), "a point behind the camera"
    half = np.tan(np.radians(SCENE_FOV / 2))
    x = (relative @ right) / depth / (half * width / height)
    y = (relative @ up) / depth / half
    return np.column_stack([(x + 1) / 2 * width, (1 - y) / 2 * height])


def arm_points(design, path):
    """World positions [m] over ``path`` of every frame of the arm's model (joints, links, tool) and both
    ends of every spring: the arm and its springs, from Pinocchio alone."""
    mechanism = design.problem.mechanism
    model, data = mechanism.model, mechanism.model.createData()
    points = []
    for q in mechanism.configurations(path):
        pin.framesForwardKinematics(model, data, q)
        points += [data.oMf[f].translation.copy() for f in range(model.nframes)]
    for starts, ends in model_end_points(design, path).values():
        points += list(starts) + list(ends)
    return np.array(points)
