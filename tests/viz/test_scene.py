"""The Meshcat scene: the helix ends against the model ends, what meshcat receives, regions, paths, the
stick figure, the static page, the springs' name labels, the camera and the legend."""

from __future__ import annotations

import re

import numpy as np
import pinocchio as pin
import pytest
import umsgpack

import springbalance as sb
from scene_helpers import (
    COLLISION_URDF,
    FLOAT32_ATOL,
    LINK1_RGB,
    URDF,
    animation_clips,
    crossing_spring,
    elbow_path,
    fixed_design,
    model_end_points,
    project,
    record_scene,
    recorded_scene,
    track_keys,
    two_link_design,
    ur5_design,
    walk,
)
from springbalance.model import sweeps
from springbalance.viz import arm, browser
from springbalance.viz import scene as viz


# ---------------------------------------------------------------------- must hold 3: ends = model ends
@pytest.mark.parametrize("make", [two_link_design, ur5_design], ids=["two_link", "ur5"])
def test_helix_ends_are_the_model_spring_ends(make):
    result = make()
    rng = np.random.default_rng(5)
    mechanism = result.problem.mechanism
    lower = np.array([j.lower for j in mechanism.joints])
    upper = np.array([j.upper for j in mechanism.joints])
    path = lower + (upper - lower) * rng.random((12, mechanism.nv))
    scene = viz.DesignScene(result, path)
    expected = model_end_points(result, path)
    lengths = result.evaluate_on(sb.Workspace.from_array(mechanism, path)).lengths  # the CasADi model's lengths
    for column, spring in enumerate(scene.springs):
        starts, ends = expected[spring.name]
        for frame in range(len(path)):
            helix = spring.helix_world(frame)
            np.testing.assert_allclose(helix[0], starts[frame], rtol=0, atol=1e-9)
            np.testing.assert_allclose(helix[-1], ends[frame], rtol=0, atol=1e-9)
            assert np.linalg.norm(helix[-1] - helix[0]) == pytest.approx(lengths[frame, column], abs=1e-9)
            # the coils keep their radius around the axis from end a to end b
            axis = (ends[frame] - starts[frame]) / lengths[frame, column]
            radial = (helix[1:-1] - starts[frame]) - np.outer((helix[1:-1] - starts[frame]) @ axis, axis)
            np.testing.assert_allclose(np.linalg.norm(radial, axis=1), spring.coil_radius, rtol=1e-9)


def _quaternion_matrix(x, y, z, w):
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def test_what_meshcat_receives_puts_the_helix_ends_on_the_model_ends(design):
    """Decode the commands sent to meshcat (mesh vertices, node transform, animation keys)
    and check the helix ends land on Pinocchio's spring ends in every frame."""
    path = sweeps.animation_path(design, frames_per_joint=8)
    scene, recorder = recorded_scene(design, path)
    expected = model_end_points(design, path)
    tree = recorder.tree
    animation = next(umsgpack.unpackb(node.animation) for node in walk(tree) if node.animation is not None)
    clips = {item["path"]: item["clip"] for item in animation["animations"]}
    for spring in scene.springs:
        node = tree["meshcat"][viz.ROOT]["springs"][spring.name]
        obj = umsgpack.unpackb(node.object)["object"]
        geometry = obj["geometries"][0]["data"]["attributes"]["position"]
        vertices = np.frombuffer(geometry["array"].data, dtype=np.float32).reshape(-1, 3)
        first, last = vertices[0].astype(float), vertices[-1].astype(float)
        np.testing.assert_array_equal(first, [0, 0, 0])
        np.testing.assert_array_equal(last, [0, 0, 1])
        # static transform (frame 0): a column-major 4×4 with the stretch in it
        matrix = np.array(umsgpack.unpackb(node.transform)["matrix"]).reshape(4, 4).T
        starts, ends = expected[spring.name]
        np.testing.assert_allclose((matrix @ np.append(first, 1))[:3], starts[0], atol=1e-9)
        np.testing.assert_allclose((matrix @ np.append(last, 1))[:3], ends[0], atol=1e-9)
        # animation: position, quaternion and scale keys of every frame
        clip = clips[f"/meshcat/{viz.ROOT}/springs/{spring.name}"]
        tracks = {track["name"]: track_keys(track) for track in clip["tracks"]}
        assert len(tracks[".position"]) == len(path)
        for frame in range(len(path)):
            rotation = _quaternion_matrix(*tracks[".quaternion"][frame])
            scale = np.array(tracks[".scale"][frame])
            position = np.array(tracks[".position"][frame])
            # key frames are float32 (FLOAT32_ATOL): the static transform above keeps float64
            np.testing.assert_allclose(position + rotation @ (scale * first), starts[frame], atol=FLOAT32_ATOL)
            np.testing.assert_allclose(position + rotation @ (scale * last), ends[frame], atol=FLOAT32_ATOL)
        colours = next(v for k, v in tracks.items() if k.endswith(".material.color"))
        np.testing.assert_allclose(colours, [scene.color_scale.rgb(t) for t in spring.tensions], atol=FLOAT32_ATOL)


def test_animation_is_replayed_after_the_objects(design):
    """A browser (or the static page) gets the tree depth first; the colour tracks bind to the
    helix meshes only if the animation comes after them."""
    _, recorder = recorded_scene(design, sweeps.animation_path(design, 8))
    order = [
        ("animation" if node.animation is not None else "object")
        for node in walk(recorder.tree)
        if node.animation is not None or node.object is not None
    ]
    assert order.count("animation") == 1 and order[-1] == "animation"


# ---------------------------------------------------------------------- regions, paths, arm, page
def test_regions_sit_on_their_bodies(design):
    path = sweeps.animation_path(design, 8)
    scene = viz.DesignScene(design, path)
    regions = {(r.spring, r.end): r for r in scene.regions}
    assert set(regions) == {("shoulder", "b"), ("forearm", "a")}  # fixed anchors have none
    segment = regions[("shoulder", "b")]
    assert segment.kind == "segment" and segment.body == "link1"
    np.testing.assert_allclose(segment.corners, [[0.24, 0, 0], [0.38, 0, 0]])  # 0.1 + [0.4, 0.8]·0.35
    box = regions[("forearm", "a")]
    assert box.kind == "box"
    np.testing.assert_allclose(box.corners, [[0.05, 0, 0.03], [0.2, 0, 0.08]])
    kinematics = sb.Workspace.from_array(design.problem.mechanism, path).kinematics().body("link1")
    np.testing.assert_allclose(box.placements[:, :3, 3], kinematics.translation, atol=1e-12)
    np.testing.assert_allclose(box.placements[:, :3, :3], kinematics.rotation, atol=1e-12)
    # each anchor of the design lies in its region
    b_point = np.array(design.spring("shoulder")["b"]["point"])
    assert 0.24 - 1e-12 <= b_point[0] <= 0.38 + 1e-12


def test_animation_path_sweeps_each_joint_and_comes_back(design):
    path = sweeps.animation_path(design, frames_per_joint=16)
    lower, upper = sweeps.workspace_ranges(design)
    np.testing.assert_allclose(path[0], (lower + upper) / 2)
    np.testing.assert_allclose(path[-1], path[0])
    np.testing.assert_allclose(path.min(axis=0), lower)
    np.testing.assert_allclose(path.max(axis=0), upper)
    moving = np.count_nonzero(np.abs(np.diff(path, axis=0)) > 0, axis=1)
    assert np.all(moving == 1)  # one joint at a time, no jumps
    assert len(path) == 1 + 2 * 16


def test_mechanism_without_visuals_is_drawn_as_a_stick_figure():
    text = (URDF / "single_link_r2.urdf").read_text()
    text = re.sub(r"<visual>.*?</visual>", "", text, flags=re.S)
    mechanism = sb.Mechanism.from_urdf_string(text, gravity=9.8)
    assert arm.visual_geometry(mechanism).ngeoms == 0
    workspace = sb.Workspace.grid(mechanism, 9)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.2, 0, 0)), stiffness=122.5
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    page = viz.scene_html(result, frames_per_joint=8)
    figure = arm.stick_figure(mechanism.model)
    names = [g.name for g in figure.geometryObjects]
    assert "joint_theta" in names and "com_theta" in names  # a joint ball and the centre of mass
    assert page.count('fetch("data:') > 10


def test_urdf_string_with_visuals_uses_them():
    mechanism = sb.Mechanism.from_urdf_string((URDF / "two_link_planar.urdf").read_text())
    geometry = arm.visual_geometry(mechanism)
    assert geometry.ngeoms == 3  # link1 box, link2 box, tool sphere
    np.testing.assert_allclose(geometry.geometryObjects[0].meshColor, [*LINK1_RGB, 1.0])


def test_static_page_is_self_contained(design):
    page = viz.scene_html(design, frames_per_joint=8)
    assert page.lstrip().startswith("<!DOCTYPE html>") and "MeshCat.Viewer" in page
    assert 'id="springbalance-legend"' in page
    # nothing is loaded from elsewhere: every command is an inline data: URL, no src/href to a server
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert not re.search(r"fetch\(\s*[\"']https?:", page)
    assert set(re.findall(r"https?://[\w.-]+", page)) <= {"http://www.w3.org"}


def _label_texts(page: str) -> dict[str, str]:
    """Text of every ``_text`` texture in a static page (its commands are inline base64 msgpack), by the
    path of the node that holds it."""
    import base64

    texts = {}
    for data in re.findall(r'fetch\("data:application/octet-binary;base64,([A-Za-z0-9+/=]+)"\)', page):
        command = umsgpack.unpackb(base64.b64decode(data))
        if command.get("type") == "set_object":
            for texture in command["object"].get("textures", []):
                if texture.get("type") == "_text":
                    texts[command["path"]] = texture["text"]
    return texts


def test_each_spring_carries_its_name_near_its_middle(design):
    path = sweeps.animation_path(design, frames_per_joint=8)
    scene = viz.DesignScene(design, path)
    names = [spring.name for spring in scene.springs]
    assert names == ["shoulder", "forearm"]
    # (adapted: text sprites are drawn only when asked for, for meshcat's own viewer; both pages draw HTML labels)
    recorder = viz.SceneRecorder()
    scene.draw(viz.meshcat.Visualizer(window=recorder), sprites=True)
    clips = animation_clips(recorder)
    ends = model_end_points(design, path)
    for spring in scene.springs:
        node = recorder.tree["meshcat"][viz.ROOT]["labels"][spring.name]
        obj = umsgpack.unpackb(node.object)["object"]
        assert obj["object"]["type"] == "Sprite"  # always faces the camera
        (texture,) = obj["textures"]
        assert texture["type"] == "_text" and texture["text"] == spring.name
        assert obj["materials"][0]["map"] == texture["uuid"]
        # the label follows the spring: in every frame it sits a fixed small height above the middle of the
        # spring's ends (from Pinocchio)
        middle = (ends[spring.name][0] + ends[spring.name][1]) / 2
        positions = np.array(clips[f"/meshcat/{viz.ROOT}/labels/{spring.name}"][".position"])
        assert positions.shape == middle.shape == (len(path), 3)
        np.testing.assert_allclose(positions[:, :2], middle[:, :2], atol=FLOAT32_ATOL)
        lift = positions[:, 2] - middle[:, 2]
        np.testing.assert_allclose(lift, lift[0], atol=FLOAT32_ATOL)
        assert 0 < lift[0] < 0.05
    # the static page draws the names in HTML (springbalance.viz.overlay), following the same nodes: no
    # sprite there, and each name with its node's path in the page's script
    page = scene.html()
    assert _label_texts(page) == {}
    for name in names:
        assert f'{{"name": "{name}", "path": ["meshcat", "{viz.ROOT}", "labels", "{name}"]' in page


def _camera(recorder):
    """World position [m] of meshcat's camera from the recorded commands, and the world point it looks at.
    meshcat's orbit controls look at the origin of the three.js scene from the ``/Cameras/default/rotated``
    node; the scene (``/meshcat``) is moved by minus the target, so the target is minus that shift."""
    transform = recorder.tree["Cameras"]["default"].transform
    if transform is not None:
        np.testing.assert_allclose(np.array(umsgpack.unpackb(transform)["matrix"]).reshape(4, 4), np.eye(4))
    shift = np.array(umsgpack.unpackb(recorder.tree["meshcat"].transform)["matrix"]).reshape(4, 4).T
    np.testing.assert_allclose(shift[:3, :3], np.eye(3))
    target = -shift[:3, 3]
    properties = [umsgpack.unpackb(p) for p in recorder.tree["Cameras"]["default"]["rotated"]["<object>"].properties]
    x, y_up, minus_y = next(p["value"] for p in properties if p["property"] == "position")
    return target + np.array([x, -minus_y, y_up]), target  # the rotated node turns meshcat's y-up back to z-up


@pytest.mark.parametrize(
    "make",
    [
        two_link_design,
        lambda: fixed_design(COLLISION_URDF, [crossing_spring()], elbow_path(np.linspace(-150, 150, 13))),
    ],
    ids=["two_link", "crossing"],
)
def test_camera_sees_every_spring_end_and_link_in_every_frame(make):
    result = make()
    path = sweeps.animation_path(result, frames_per_joint=12)
    scene = viz.DesignScene(result, path)
    camera, target = _camera(record_scene(scene))
    np.testing.assert_allclose(camera, scene.camera_position, atol=1e-12)
    np.testing.assert_allclose(target, scene.camera_target, atol=1e-12)
    ends = model_end_points(result, path)
    mechanism = result.problem.mechanism
    model, data = mechanism.model, mechanism.model.createData()
    links = []
    for q in mechanism.configurations(path):
        pin.framesForwardKinematics(model, data, q)
        links += [data.oMf[f].translation.copy() for f in range(model.nframes)]  # joints, link ends, tool
    points = np.vstack([np.vstack(pair) for pair in ends.values()] + [np.array(links)])
    # within the bounding sphere, and within meshcat's field of view (75° vertical, the window's aspect)
    # (this test asked for a cone of 75° about the line of sight to the world origin before the camera
    # looked at the arm's centre and fitted the view's rectangle)
    assert np.all(np.linalg.norm(points - scene.camera_center, axis=1) <= scene.camera_radius + 1e-12)
    pixels = project(scene, points)
    width, height = browser.WINDOW
    assert np.all((pixels >= 0) & (pixels <= [width, height])), (pixels.min(axis=0), pixels.max(axis=0))
    spread = (pixels.max(axis=0) - pixels.min(axis=0)) / [width, height]
    assert spread.max() > 0.5, spread  # and the camera is not so far that the arm is a speck


def test_legend_pushing_part_only_for_a_spring_that_pushes():
    """A compression spring from (0, 0, -0.3) to (0.2, 0, 0) on link1 is L = sqrt(0.13 + 0.12 sin s) long
    (shoulder s, elbow free); with l0 = 0.3 m its tension k (L - l0) is negative (it pushes) for
    sin s < -1/3 only. The design's workspace covers both, the legend follows the animation's frames."""
    spring = sb.CompressionSpring(
        sb.Anchor("universe", (0.0, 0.0, -0.3)),
        sb.Anchor("link1", (0.2, 0.0, 0.0)),
        name="strut",
        stiffness=200.0,
        free_length=0.3,
    )
    shoulder = np.radians(np.linspace(-90, 90, 13))
    result = fixed_design(URDF / "two_link_planar.urdf", [spring], np.column_stack([shoulder, np.zeros(13)]))
    pushing_in_design = 200.0 * (np.sqrt(0.13 + 0.12 * np.sin(shoulder)) - 0.3)
    assert np.any(pushing_in_design < -1) and np.any(pushing_in_design > 1)

    def scene_over(degrees):
        angles = np.radians(degrees)
        scene = viz.DesignScene(result, np.column_stack([angles, np.zeros_like(angles)]))
        np.testing.assert_allclose(
            scene.springs[0].tensions, 200.0 * (np.sqrt(0.13 + 0.12 * np.sin(angles)) - 0.3), rtol=1e-9
        )
        return scene

    lifting = scene_over(np.linspace(0, 90, 7))  # L ≥ sqrt(0.13) > 0.3: never pushes
    assert not lifting.compression
    assert "pushing" not in lifting.legend_html() and "pushing" not in lifting.html(animate=False)
    assert not re.search(r">-\d", lifting.legend_html())  # no negative tick
    lowering = scene_over(np.linspace(-90, 0, 7))  # pushes below s = -19.5°
    assert lowering.compression
    assert "(negative: pushing)" in lowering.legend_html() and re.search(r">-\d", lowering.legend_html())
