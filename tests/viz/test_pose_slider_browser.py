"""The pose slider used for real in headless Chromium (DevTools protocol, :mod:`springbalance.viz.devtools`): on
the static scene.html and on the live page of `view`. Moving the slider moves the drawn arm to that pose (its
links' transforms read from the page's scene graph equal Pinocchio's placements; the screenshot changes where the
arm is) and the overlay shows that pose's spring forces and residual torques, computed here independently
(Hooke's law on Pinocchio's anchor points; the design evaluated at that one pose)."""

from __future__ import annotations

import re
import time
import urllib.request

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from cli_helpers import until_ctrl_c
from scene_helpers import LINK1_RGB, URDF, model_end_points, require_chromium, ur5_design
from springbalance.viz import browser
from springbalance.viz import scene as viz
from springbalance.viz.devtools import PageSession
from springbalance.viz.live import MeshcatServer, publish_scene
from springbalance.viz.pose_data import PoseData
from springbalance.viz.pose_slider import SLIDER_ID, pose_slider_html

pytestmark = pytest.mark.slow  # every test here opens headless Chromium

READY = "window.springbalancePoses && springbalancePoses.ready()"
#: the world matrix of a node relative to meshcat's root (which turns z-up into three.js's y-up), column-major
RELATIVE = (
    "(function (path) { viewer.scene.updateMatrixWorld(true);"
    " var root = viewer.scene_tree.find(['meshcat']).object.matrixWorld.clone().invert();"
    " return Array.from(root.multiply(viewer.scene_tree.find(path).object.matrixWorld).elements); })"
)


def _node_matrix(page: PageSession, path: list[str]) -> np.ndarray:
    return np.array(page.evaluate(f"{RELATIVE}({path!r})")).reshape(4, 4).T


def _move_slider(page: PageSession, pose: int) -> None:
    """Set the slider to ``pose`` (1-based, as the page shows it) as a user's drag does: value, then 'input'."""
    page.evaluate(
        f"(function () {{ var s = document.getElementById('{SLIDER_ID}'); s.value = '{pose}';"
        " s.dispatchEvent(new Event('input', {bubbles: true})); })()"
    )


def _overlay(page: PageSession) -> dict[tuple[str, int], tuple[float, str]]:
    cells = page.evaluate(
        "Array.from(document.querySelectorAll('.springbalance-number'))"
        ".map(e => [e.dataset.field, Number(e.dataset.row), Number(e.dataset.value), e.textContent])"
    )
    return {(field, row): (value, text) for field, row, value, text in cells}


def _link2_placement(design, q_values: np.ndarray) -> np.ndarray:
    """Pinocchio's placement (4×4) of link2's visual geometry at joint values ``q_values`` [rad]."""
    mechanism = design.problem.mechanism
    model = mechanism.model
    visual = pin.buildGeomFromUrdf(model, str(URDF / "two_link_planar.urdf"), pin.GeometryType.VISUAL)
    data, visual_data = model.createData(), visual.createData()
    pin.forwardKinematics(model, data, mechanism.configurations(q_values[None])[0])
    pin.updateGeometryPlacements(model, data, visual, visual_data)
    return visual_data.oMg[visual.getGeometryId("link2_0")].homogeneous


def _check_pose(page: PageSession, design, scene, frame: int) -> None:
    """The page shows pose ``frame`` (0-based): the slider, the arm's link2, the shoulder spring, the numbers."""
    assert page.evaluate("springbalancePoses.frame()") == frame
    assert page.evaluate(f"document.getElementById('{SLIDER_ID}').value") == str(frame + 1)
    assert page.evaluate("document.getElementById('springbalance-pose-label').textContent") == (
        f"pose {frame + 1} of {scene.size}"
    )
    q = scene.joint_values[frame]
    drawn = _node_matrix(page, ["meshcat", "pinocchio", "visuals", "link2_0"])
    np.testing.assert_allclose(drawn, _link2_placement(design, q), atol=1e-6)
    # the shoulder spring's node starts at its end a and is stretched to its length (scale of its z axis)
    a, b = model_end_points(design, q[None])["shoulder"]
    spring = _node_matrix(page, ["meshcat", "springbalance", "springs", "shoulder"])
    np.testing.assert_allclose(spring[:3, 3], a[0], atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(spring[:3, 2]), np.linalg.norm(b[0] - a[0]), rtol=1e-6)
    # the numbers: the design evaluated at this one pose, and Hooke's law on the ends from Pinocchio
    alone = design.evaluate_on(sb.Workspace.from_array(design.problem.mechanism, q[None]))
    overlay = _overlay(page)
    for joint in range(2):
        assert overlay[("q", joint)][0] == pytest.approx(np.degrees(q[joint]), rel=1e-5, abs=1e-9)
        value, text = overlay[("tau", joint)]
        assert value == pytest.approx(alone.tau[0, joint], rel=1e-5, abs=1e-9)
        assert float(text) == pytest.approx(alone.tau[0, joint], rel=5e-4, abs=1e-9)  # four significant digits
    ends = model_end_points(design, q[None])
    for column, record in enumerate(design.springs):
        start, end = ends[record["name"]]
        length = float(np.linalg.norm(end[0] - start[0]))
        force = record.get("initial_tension", 0.0) + record["stiffness"] * (length - record["free_length"])
        value, text = overlay[("force", column)]
        assert value == pytest.approx(force, rel=1e-5) and float(text) == pytest.approx(force, rel=5e-4)
        assert overlay[("length", column)][0] == pytest.approx(1e3 * length, rel=1e-5)


def _check_panel_box(page: PageSession) -> None:
    """The slider's panel lies inside browser.POSES_BOX, which the screenshot censuses leave out."""
    box = page.evaluate(
        "(function () { var r = document.getElementById('springbalance-poses').getBoundingClientRect();"
        " return [r.left, r.top, r.right, r.bottom]; })()"
    )
    left, top, right, bottom = browser.POSES_BOX
    assert left <= box[0] and top <= box[1] and box[2] <= right and box[3] <= bottom, box


def test_ur5_panel_fits_its_box(tmp_path):
    """Six joints and two springs, and seven joints and six springs: the panel fits the box the censuses leave out."""
    require_chromium()
    page_file = tmp_path / "ur5.html"
    page_file.write_text(viz.DesignScene(ur5_design(), frames_per_joint=4).html(autoplay=False))
    with PageSession(page_file) as page:
        page.wait_for(READY)
        _check_panel_box(page)
        # the most the box is made for: 7 joints and 6 springs with long names and wide numbers
        data = PoseData(
            30.0,
            [{"name": f"shoulder_lift_joint_{i}", "unit": "deg", "torque_unit": "N·m"} for i in range(7)],
            [{"name": f"spring_{i}", "type": "extension", "force_unit": "N", "length_unit": "mm"} for i in range(6)],
            [[-123.456] * 7] * 2,
            [[-12.3456] * 7] * 2,
            [[-12.3456] * 7] * 2,
            [[-1234.56] * 6] * 2,
            [[1234.56] * 6] * 2,
            title="the 12 worst poses (largest residual torque first)",
        )
        crowded = tmp_path / "crowded.html"
        crowded.write_text(f"<!DOCTYPE html><html><body>{pose_slider_html(data)}</body></html>")
        page.navigate(crowded)
        _check_panel_box(page)


def _arm_pixels(image) -> np.ndarray:
    from PIL import Image

    with Image.open(image) as picture:
        rgb = np.asarray(picture.convert("RGB"), dtype=float) / 255.0
    mask = browser.hue_mask(rgb, LINK1_RGB)
    left, top, right, bottom = browser.POSES_BOX
    mask[top:bottom, left:right] = False  # the slider's panel is not the arm
    return mask


def test_static_scene_slider_moves_the_arm_and_shows_that_poses_numbers(design, tmp_path):
    require_chromium()
    scene = viz.DesignScene(design, frames_per_joint=8)
    page_file = tmp_path / "scene.html"
    page_file.write_text(scene.html())  # as the report writes it: the animation plays
    shoulder_up = int(np.argmax(scene.joint_values[:, 0]))  # the shoulder at its upper limit, +80°
    with PageSession(page_file) as page:
        page.wait_for(READY)
        assert page.evaluate(f"document.getElementById('{SLIDER_ID}').type") == "range"
        assert page.evaluate(f"document.getElementById('{SLIDER_ID}').max") == str(scene.size)
        _check_panel_box(page)
        # while the animation plays, the slider follows it
        seen = set()
        for _ in range(12):
            seen.add(page.evaluate("springbalancePoses.frame()"))
            time.sleep(0.05)
        assert len(seen) > 1, seen
        _move_slider(page, 1)
        _check_pose(page, design, scene, 0)
        first = _arm_pixels(page.screenshot(tmp_path / "first.png"))
        _move_slider(page, shoulder_up + 1)
        _check_pose(page, design, scene, shoulder_up)  # paused there: the animation does not run on
        raised = _arm_pixels(page.screenshot(tmp_path / "raised.png"))
        assert first.sum() > 300 and raised.sum() > 300, (first.sum(), raised.sum())
        # link1 turned by 80°: most of its pixels are elsewhere
        assert (first ^ raised).sum() > 0.5 * (first.sum() + raised.sum()), ((first ^ raised).sum(), first.sum())
        # the keyboard: the slider has the focus, → is the next pose
        page.evaluate(f"document.getElementById('{SLIDER_ID}').focus()")
        for kind in ("rawKeyDown", "keyUp"):
            page.call(
                "Input.dispatchKeyEvent", type=kind, key="ArrowRight", code="ArrowRight", windowsVirtualKeyCode=39
            )
        page.wait_for(f"springbalancePoses.frame() === {shoulder_up + 1}", timeout=10)
        _check_pose(page, design, scene, shoulder_up + 1)
        # an address with #pose=K opens the page at pose K
        page.navigate("about:blank")
        page.navigate(f"{page_file.resolve().as_uri()}#pose=14")
        page.wait_for(READY)
        _check_pose(page, design, scene, 13)


def test_live_view_page_has_the_same_slider(design):
    require_chromium()
    scene = viz.DesignScene(design, frames_per_joint=8)
    server = MeshcatServer()
    try:
        scene.draw(server.visualizer())
        url = publish_scene(server, scene)
        assert url.startswith("http://127.0.0.1:") and url.endswith("/springbalance/")
        with PageSession(url) as page:
            page.wait_for(READY)
            assert page.evaluate("document.getElementById('springbalance-legend') !== null")
            _move_slider(page, 11)  # elbow at its upper limit
            _check_pose(page, design, scene, 10)
            _move_slider(page, 3)
            _check_pose(page, design, scene, 2)
    finally:
        server.stop()


def test_view_prints_and_serves_its_slider_page(design_file):
    """`view --poses worst:4`: the first line names the page on 127.0.0.1, which is served there with four poses."""
    require_chromium()
    pages = []

    def check(process, first):
        match = re.search(r"http://127\.0\.0\.1:(\d+)/springbalance/", first)
        assert match is not None and "/static/" in first, first  # the slider page, and meshcat's own viewer
        with urllib.request.urlopen(match.group(0), timeout=10) as response:
            assert response.status == 200
            pages.append(response.read().decode("utf-8"))
        with PageSession(match.group(0)) as page:
            page.wait_for(READY)
            assert page.evaluate(f"document.getElementById('{SLIDER_ID}').max") == "4"
            assert page.evaluate("springbalancePoses.data.title") == "the 4 worst poses (largest residual torque first)"

    code, out, err = until_ctrl_c(["view", str(design_file), "--poses", "worst:4"], check)
    assert "Traceback" not in err and "stopped" in out, err
    assert 'src="/static/main.min.js"' in pages[0]
