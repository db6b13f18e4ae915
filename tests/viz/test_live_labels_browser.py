"""The live page of `view` (meshcat's viewer on the 127.0.0.1 server, with the scene's own overlay) places the
springs' name labels as the static page does: in headless Chromium, once the scene has arrived over the
websocket, every spring has one label, inside the view, off the page's panels (legend, pose slider, anchor
regions' checkbox), and no two labels overlap (their boxes from the DOM). Eight springs with long names side by
side crowd the view, so that the layout has to move labels, or shrink them to dots that name themselves on hover."""

from __future__ import annotations

import dataclasses
import itertools

import pytest

from scene_helpers import require_chromium, two_link_design
from springbalance.model import sweeps
from springbalance.viz import browser
from springbalance.viz import scene as viz
from springbalance.viz.devtools import PageSession
from springbalance.viz.live import MeshcatServer, publish_scene

pytestmark = pytest.mark.slow  # headless Chromium and a meshcat server

PANELS = ("springbalance-legend", "springbalance-poses", "springbalance-controls")


def _overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def test_live_page_labels_do_not_overlap():
    require_chromium()
    design = two_link_design()
    scene = viz.DesignScene(design, sweeps.animation_path(design, frames_per_joint=4))
    template = scene.springs[0]
    scene.springs = [
        dataclasses.replace(template, name=f"a_rather_long_spring_name_{index}", starts=template.starts + 0.01 * index)
        for index in range(8)
    ]
    server = MeshcatServer()
    try:
        scene.draw(server.visualizer())
        url = publish_scene(server, scene)
        assert url.startswith("http://127.0.0.1:")
        with PageSession(url) as page:
            # the labels' nodes have arrived (the first spring's label node has its position) and are placed
            label = ["meshcat", viz.ROOT, "labels", "a_rather_long_spring_name_0"]
            page.wait_for(
                "document.querySelectorAll('.sb-label[data-box]').length === 8 && "
                f"viewer.scene_tree.find({label!r}).object.position.length() > 0",
                timeout=30,
            )
            page.evaluate("new Promise(function (done) { setTimeout(done, 500); })")
            boxes = browser.label_boxes(page.evaluate("document.documentElement.outerHTML"))
            panels = page.evaluate(
                f"{list(PANELS)!r}.map(function (id) {{ var e = document.getElementById(id); if (!e) {{ return null; }}"
                " var r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; })"
            )
    finally:
        server.stop()
    assert set(boxes) == {spring.name for spring in scene.springs}
    assert all(panel is not None for panel in panels), panels  # legend, slider and checkbox are on the page
    width, height = browser.WINDOW
    for name, (mode, box) in boxes.items():
        assert mode in ("label", "dot") and 0 <= box[0] and box[2] <= width and 0 <= box[1] and box[3] <= height
        for panel in panels:
            assert not _overlap(box, panel) or mode == "dot", (name, box, panel)
    for (a, (_, box_a)), (b, (_, box_b)) in itertools.combinations(boxes.items(), 2):
        assert not _overlap(box_a, box_b), (a, box_a, b, box_b)
