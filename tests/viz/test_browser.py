"""The static page rendered for real in headless Chromium (skipped where Chromium is not installed)."""

from __future__ import annotations

import colorsys

import pytest

from scene_helpers import (
    COLLISION_URDF,
    LINK1_RGB,
    MARGIN,
    crossing_spring,
    elbow_path,
    fixed_design,
    meshcat,
    require_chromium,
)
from springbalance.viz import browser, colors
from springbalance.viz import scene as viz
from springbalance.viz.recorder import SceneRecorder

pytestmark = pytest.mark.slow  # every test here opens headless Chromium


def test_scene_renders_in_headless_chromium(design, tmp_path):
    require_chromium()
    # the report's scene (animation playing): the arm's blue and the springs' colours are on screen
    report = design.report(tmp_path / "out")
    shot = browser.screenshot(report.parent / "scene.html", tmp_path / "scene.png")
    census = browser.colour_census(shot, [LINK1_RGB], browser.scale_colours())
    assert census.ok(), census
    # a still of the first frame: each spring shows the colour of its own tension there
    scene = viz.DesignScene(design, frames_per_joint=8)
    still = tmp_path / "still.html"
    still.write_text(scene.html(autoplay=False))
    shot = browser.screenshot(still, tmp_path / "still.png")
    for spring in scene.springs:
        colour = scene.color_scale.rgb(spring.tensions[0])
        census = browser.colour_census(shot, [LINK1_RGB], [colour])
        assert census.arm >= 150 and census.spring >= 40, (spring.name, colour, census)
    # the stiff shoulder spring is red, the soft forearm spring yellow: hues more than twice the
    # census tolerance apart, so the two counts above are of different pixels
    shoulder, forearm = (360 * colorsys.rgb_to_hsv(*scene.color_scale.rgb(s.tensions[0]))[0] for s in scene.springs)
    assert abs(forearm - shoulder) > 2 * 14


def test_chromium_census_finds_nothing_on_an_empty_scene(tmp_path):
    """Negative control: the page around the scene (background, grid, controls, legend) counts as
    neither arm nor spring. (meshcat's coordinate axes would, in red, green and blue: the scene
    hides them, as here.)"""
    require_chromium()
    recorder = SceneRecorder()
    visualizer = meshcat.Visualizer(window=recorder)
    visualizer["/Axes"].set_property("visible", False)
    visualizer["/Background"].set_property("top_color", [1.0, 1.0, 1.0])
    visualizer["/Background"].set_property("bottom_color", [0.8, 0.83, 0.88])
    page = tmp_path / "empty.html"
    page.write_text(viz._insert_before_body_end(visualizer.static_html(), colors.ColorScale(100).legend_html(True)))
    census = browser.colour_census(
        browser.screenshot(page, tmp_path / "empty.png"), [LINK1_RGB], browser.scale_colours()
    )
    assert census.arm < 5 and census.spring < 5, census


def test_red_spring_renders_in_headless_chromium(tmp_path):
    require_chromium()
    path = elbow_path([120])  # link2 passes through the spring
    scene = viz.DesignScene(fixed_design(COLLISION_URDF, [crossing_spring()], path), path, margin=MARGIN)
    page = tmp_path / "clearance.html"
    page.write_text(scene.html(autoplay=False))
    census = browser.colour_census(
        browser.screenshot(page, tmp_path / "clearance.png"), [LINK1_RGB], [colors.CLEARANCE_RGB]
    )
    assert census.arm >= 150 and census.spring >= 40, census
