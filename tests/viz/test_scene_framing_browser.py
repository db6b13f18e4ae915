"""The framing as a person checks it, in headless Chromium on the real page: the arm and its springs at the pose
the page opens at fill at least half the view (the larger side of their projected box), and at every pose the
slider offers they stay within the view. The projected box is measured on the page itself: every vertex of every
visible mesh under meshcat's ``/meshcat`` node (the arm's links, the springs' helices, their anchors) projected
with the page's three.js camera, at each pose the slider sets. Issue 30 asked for "at least half the view". Measured
the same way on the framing before this one (camera on the middle of the whole animation's bounding spheres, 75°
field of view), the first pose covered 0.31 × 0.15 of the view (area share 0.047) for the demo and 0.17 × 0.47
(0.082) for the UR5 example; the area floor below is well above both."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from scene_helpers import require_chromium
from springbalance.io.config import load_config
from springbalance.viz import browser
from springbalance.viz import scene as viz
from springbalance.viz.devtools import PageSession

pytestmark = pytest.mark.slow  # headless Chromium

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
READY = "window.springbalancePoses && springbalancePoses.ready()"
#: the projected box [px] (left, top, right, bottom) of every vertex of the visible meshes under /meshcat
BOX = """(function () {
  viewer.scene.updateMatrixWorld(true);
  var camera = viewer.camera; camera.updateMatrixWorld(); camera.updateProjectionMatrix();
  var W = viewer.renderer.domElement.clientWidth, H = viewer.renderer.domElement.clientHeight;
  var v = new camera.position.constructor(), box = [Infinity, Infinity, -Infinity, -Infinity];
  function shown(o) { for (; o; o = o.parent) { if (!o.visible) { return false; } } return true; }
  viewer.scene_tree.find(["meshcat"]).object.traverse(function (o) {
    if (!o.isMesh || !shown(o)) { return; }
    var p = o.geometry.attributes.position;
    for (var i = 0; i < p.count; i++) {
      v.fromBufferAttribute(p, i).applyMatrix4(o.matrixWorld).project(camera);
      var x = (v.x + 1) / 2 * W, y = (1 - v.y) / 2 * H;
      box = [Math.min(box[0], x), Math.min(box[1], y), Math.max(box[2], x), Math.max(box[3], y)];
    }
  });
  return box;
})()"""


def _example(name: str) -> sb.DesignResult:
    """The example's problem at its first guess (the framing depends on the arm and the springs' places only)."""
    problem = load_config(EXAMPLES / name).problem
    return sb.DesignResult(problem, np.array(problem.variables.start))


@pytest.mark.parametrize("name", ["two_link.yaml", "ur5.yaml"])
def test_the_first_pose_fills_half_the_view_and_every_pose_stays_in_it(name, tmp_path):
    require_chromium()
    scene = viz.DesignScene(_example(name), frames_per_joint=8)
    page_file = tmp_path / "scene.html"
    page_file.write_text(scene.html(autoplay=False))
    width, height = browser.WINDOW
    with PageSession(page_file) as page:
        page.wait_for(READY)
        assert page.evaluate("[innerWidth, innerHeight]") == [width, height]
        first = page.evaluate(BOX)
        share = np.array([(first[2] - first[0]) / width, (first[3] - first[1]) / height])
        assert share.max() >= 0.5, share
        assert share.prod() >= 0.12, share  # 0.047 and 0.082 before (module docstring)
        boxes = []
        for pose in range(scene.size):
            page.evaluate(f"springbalancePoses.set({pose})")
            boxes.append(page.evaluate(BOX))
    boxes = np.array(boxes)
    assert np.allclose(boxes[0], first)  # the page opens at the first pose
    left, top = boxes[:, :2].min(axis=0)
    right, bottom = boxes[:, 2:].max(axis=0)
    assert 0 <= left and 0 <= top and right <= width and bottom <= height, (left, top, right, bottom)
    # and the camera is not far away: the motion spans most of the view one way or the other
    assert max((right - left) / width, (bottom - top) / height) >= 0.85, (left, top, right, bottom)
