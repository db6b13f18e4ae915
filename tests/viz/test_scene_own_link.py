"""A spring that runs inside its own anchor link beyond its anchor (the report's ``inside_own_link``) is drawn
red with a marker where it runs inside, like a spring below the clearance margin.

The arm is urdf/two_link_planar_collision.urdf: link1's collision box is 0.5 × 0.04 × 0.04 m, centred 0.25 m
along link1's x axis; the shoulder turns about (0, -1, 0), so at a shoulder angle θ link1 points along
(cos θ, 0, sin θ). The spring "sloped" runs from A = (0.1, 0, 0) on link1's axis (20 mm deep in the box) to
the ground point G = (0.5, 0, 0.1). The rule (results/own_link.py) exempts the first d + r + 3 mm of it from A
(d = 20 mm: A's way out of the box; r = 10 mm: the capsule of a spring without a spec sheet); beyond that the
line climbs (or sinks) through the box, so its deepest point is where the exempt stretch ends, S = A + 33 mm · u,
|z_S| below the top (or bottom) face, 20 mm − |z_S| deep in link1's frame; the face's point nearest it is
straight above (below) it. Worked out here in link1's frame from the box alone.
"""

from __future__ import annotations

import numpy as np
import pytest

import springbalance as sb
from scene_helpers import CAPSULE_RADIUS, COLLISION_URDF, animation_clips, fixed_design, record_scene
from springbalance.results.own_link import inside_own_link
from springbalance.viz import colors
from springbalance.viz import scene as viz

ANCHOR, GROUND = np.array([0.1, 0.0, 0.0]), np.array([0.5, 0.0, 0.1])  # [m]: A on link1, G on the ground
HALF_THICKNESS = 0.02  # [m] of link1's box
EXEMPT = HALF_THICKNESS + CAPSULE_RADIUS + 0.003  # [m] from A: the anchor's own stretch
MARKER = CAPSULE_RADIUS + 0.012  # [m] the marker's radius beyond nothing (clearance markers' look)


def _expected(shoulder: float) -> tuple[float, np.ndarray | None]:
    """Depth [m] and marker point (world) [m] at shoulder angle ``shoulder`` [rad], from the box alone."""
    along, across = (
        np.array([np.cos(shoulder), 0, np.sin(shoulder)]),
        np.array([-np.sin(shoulder), 0, np.cos(shoulder)]),
    )
    ground = np.array([GROUND @ along, 0.0, GROUND @ across])  # G in link1's frame
    axis = (ground - ANCHOR) / np.linalg.norm(ground - ANCHOR)
    deepest = ANCHOR + EXEMPT * axis
    depth = HALF_THICKNESS - abs(deepest[2])  # nearest face: top or bottom (the sides are 20 mm away)
    if depth <= 0:
        return 0.0, None
    surface = np.array([deepest[0], 0.0, np.sign(deepest[2]) * HALF_THICKNESS])
    middle = (deepest + surface) / 2
    return depth, middle[0] * along + middle[2] * across


def test_a_spring_inside_its_own_link_has_a_marker_where_it_runs_inside():
    degrees = [0.0, 30.0, -60.0]
    path = np.column_stack([np.radians(degrees), np.zeros(3)])
    spring = sb.ExtensionSpring(sb.Anchor("link1", tuple(ANCHOR)), sb.Anchor("universe", tuple(GROUND)), "sloped",
                                stiffness=100.0, free_length=0.05)  # fmt: skip
    design = fixed_design(COLLISION_URDF, [spring], path)
    found = inside_own_link(design)  # what the report flags, over the same poses
    assert [(f.spring, f.body) for f in found] == [("sloped", "link1")]
    scene = viz.DesignScene(design, path, flagged={"sloped": "runs inside link1 beyond its anchor"})
    clip = animation_clips(record_scene(scene))[f"/meshcat/{viz.ROOT}/markers/sloped"]
    expected = [_expected(angle) for angle in path[:, 0]]
    assert [depth > 0 for depth, _ in expected] == [True, True, False]  # at -60° it leaves the box in its stretch
    assert max(depth for depth, _ in expected) == pytest.approx(found[0].depth, abs=2e-5)
    for frame, (depth, point) in enumerate(expected):
        assert scene.rgb(scene.springs[0], frame) == colors.CLEARANCE_RGB
        if point is None:
            assert max(clip[".scale"][frame]) < 1e-5  # no marker where the spring is outside its link
            continue
        # halfway between the deepest point and link1's face, grown by half the depth: it reaches a marker's
        # radius out of the link, where it can be seen
        np.testing.assert_allclose(clip[".position"][frame], point, atol=2e-5)
        np.testing.assert_allclose(clip[".scale"][frame], [(MARKER + depth / 2) / MARKER] * 3, atol=1e-3)
    assert "sloped: runs inside link1 beyond its anchor" in scene.legend_html()


def test_a_spring_that_is_not_flagged_gets_no_own_link_marker():
    path = np.array([[0.0, 0.0]])
    spring = sb.ExtensionSpring(sb.Anchor("link1", tuple(ANCHOR)), sb.Anchor("universe", tuple(GROUND)), "sloped",
                                stiffness=100.0, free_length=0.05)  # fmt: skip
    scene = viz.DesignScene(fixed_design(COLLISION_URDF, [spring], path), path)
    assert scene.springs[0].inside is None
    assert "markers" not in record_scene(scene).tree["meshcat"][viz.ROOT].keys()


def test_the_legend_says_where_the_marker_is():
    path = np.array([[0.0, 0.0]])
    spring = sb.ExtensionSpring(sb.Anchor("link1", tuple(ANCHOR)), sb.Anchor("universe", tuple(GROUND)), "sloped",
                                stiffness=100.0, free_length=0.05)  # fmt: skip
    flagged = {"sloped": "runs inside link1 beyond its anchor"}
    legend = viz.DesignScene(fixed_design(COLLISION_URDF, [spring], path), path, flagged=flagged).legend_html()
    assert "red: the springs named below, ● where each runs into a link" in legend and "too close" not in legend
