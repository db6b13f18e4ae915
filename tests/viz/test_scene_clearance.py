"""Springs that fit the arm: in the frames where a spring is below the clearance margin it is solid red,
with a marker at its closest point, and the legend names it."""

from __future__ import annotations

import colorsys

import numpy as np
import pytest
import umsgpack

import springbalance as sb
from scene_helpers import (
    CAPSULE_RADIUS,
    COLLISION_URDF,
    CROSSING_P,
    CROSSING_S,
    ELBOW,
    FLOAT32_ATOL,
    LINK1_RGB,
    LINK2_HALF_WIDTH,
    LINK2_LENGTH,
    MARGIN,
    URDF,
    animation_clips,
    crossing_spring,
    elbow_path,
    fixed_design,
    hue_distance,
    record_scene,
)
from springbalance.viz import browser, colors
from springbalance.viz import scene as viz

# the crossing spring on urdf/two_link_planar_collision.urdf: see scene_helpers (COLLISION_URDF)


def _crosses_link2_axis(elbow: float) -> bool:
    """Does the spring's segment S–P cross link2's centre line E + t (cos e, 0, sin e), 0 ≤ t ≤ 0.4?
    Where it does, the capsule around the spring holds a point inside link2's box: an overlap."""
    axis = np.array([np.cos(elbow), np.sin(elbow)])  # in the x–z plane
    spring = (CROSSING_P - CROSSING_S)[[0, 2]]
    u, t = np.linalg.solve(np.column_stack([spring, -axis]), (ELBOW - CROSSING_S)[[0, 2]])
    return 0 <= u <= 1 and 0 <= t <= LINK2_LENGTH


def test_clearance_colour_is_not_on_the_tension_scale():
    """The clearance colour is pure red (hue 0°, saturation and value 1). The tension scale passes
    through reds on its way from orange to its dark raspberry end (0.55, 0, 0.32) (hue 325°), but none of
    them is that saturated: on the segment from orange (0.96, 0.43, 0.16) to that end, green equals blue
    (hue 0°) at t = 0.27 / 0.59 ≈ 0.46, where the colour is (0.77, 0.23, 0.23), saturation 0.70; every
    colour within 14° of red stays below 0.85, so red at saturation ≥ 0.9 is told apart from every
    tension (and link1's blue). (This test
    asked for a hue 28° away from the scale when the clearance colour was magenta.)"""
    r, g, b = colors.CLEARANCE_RGB
    assert colorsys.rgb_to_hsv(r, g, b) == (0.0, 1.0, 1.0)
    for colour in browser.scale_colours(401) + [LINK1_RGB]:
        hue, saturation, _ = colorsys.rgb_to_hsv(*colour)
        if hue_distance(colors.CLEARANCE_RGB, colour) <= 14:
            assert saturation < 0.85, colour
    strict = browser.hue_mask(
        np.array([browser.scale_colours(401) + [LINK1_RGB]]), colors.CLEARANCE_RGB, min_saturation=0.9
    )
    assert not strict.any()
    assert browser.hue_mask(np.array([[colors.CLEARANCE_RGB]]), colors.CLEARANCE_RGB, min_saturation=0.9).all()
    assert f"#{colors.CLEARANCE_COLOR:06x}" in colors.ColorScale(10).legend_html(clearance_margin=0.012)


def _distance_to_link2(point: np.ndarray, elbow: float) -> float:
    """Distance [m] from a world point to link2's collision box (0 inside): the box runs 0.4 m from the
    elbow E along (cos e, 0, sin e), 0.03 m square across (the URDF's numbers, see scene_helpers)."""
    axis, across = np.array([np.cos(elbow), 0.0, np.sin(elbow)]), np.array([-np.sin(elbow), 0.0, np.cos(elbow)])
    relative = point - ELBOW
    local = np.array([relative @ axis - LINK2_LENGTH / 2, relative[1], relative @ across])
    return float(np.linalg.norm(np.maximum(np.abs(local) - [LINK2_LENGTH / 2, LINK2_HALF_WIDTH, LINK2_HALF_WIDTH], 0)))


def _distance_to_spring(point: np.ndarray) -> float:
    """Distance [m] from a world point to the spring's centre line S–P."""
    direction = CROSSING_P - CROSSING_S
    t = np.clip((point - CROSSING_S) @ direction / (direction @ direction), 0.0, 1.0)
    return float(np.linalg.norm(point - (CROSSING_S + t * direction)))


def test_spring_is_red_with_a_marker_where_it_passes_through_link2():
    degrees = [-90, -45, 0, 75, 90, 120, 150]
    path = elbow_path(degrees)
    crossing = [_crosses_link2_axis(e) for e in path[:, 1]]
    assert crossing == [False, False, False, True, True, True, True]  # the geometry above, worked out
    result = fixed_design(COLLISION_URDF, [crossing_spring()], path)
    scene = viz.DesignScene(result, path, margin=MARGIN)
    track = scene.springs[0]
    assert track.radius == CAPSULE_RADIUS
    # where link2's centre line crosses the spring, the capsule overlaps link2's box
    assert np.all(track.clearance[3:] < 0) and np.all(track.below_margin[3:])
    # elbow at -90°: link2 hangs down from E, so its box spans x ∈ [0.485, 0.515], z ∈ [-0.4, 0]; the box's
    # corner (0.485, ·, 0) is the point closest to the line S–P (whose foot lies within the segment), at
    # |(0.485 - 0.4)·0.25 - 0·0.2| / |(0.2, 0.25)| from it. link1 (the spring's anchor body) is exempt,
    # though S lies inside its box.
    direction = (CROSSING_P - CROSSING_S)[[0, 2]]
    corner = np.array([ELBOW[0] - LINK2_HALF_WIDTH, 0.0]) - CROSSING_S[[0, 2]]
    foot = corner @ direction / (direction @ direction)
    assert 0 < foot < 1
    expected = abs(corner[0] * direction[1] - corner[1] * direction[0]) / np.linalg.norm(direction) - CAPSULE_RADIUS
    assert track.clearance[0] == pytest.approx(expected, abs=1e-6)
    assert expected > MARGIN and not track.below_margin[0]
    # what meshcat receives: the colour track is red in the crossing frames, the tension colour elsewhere
    recorder = record_scene(scene)
    helix = umsgpack.unpackb(recorder.tree["meshcat"][viz.ROOT]["springs"]["crossing"].object)["object"]
    assert helix["materials"][0]["color"] == scene.color_scale.hex(track.tensions[0])  # frame 0 is clear
    clip = animation_clips(recorder)[f"/meshcat/{viz.ROOT}/springs/crossing"]
    colours = next(values for name, values in clip.items() if name.endswith(".material.color"))
    markers = animation_clips(recorder)[f"/meshcat/{viz.ROOT}/markers/crossing"]
    for frame, crosses in enumerate(crossing):
        if crosses:
            np.testing.assert_allclose(colours[frame], colors.CLEARANCE_RGB, atol=FLOAT32_ATOL)
            # the marker, full size, halfway between the spring's capsule and link2 where they come closest:
            # inside both the capsule (radius 10 mm about S–P) and link2's box grown by that radius
            np.testing.assert_allclose(markers[".scale"][frame], [1, 1, 1], atol=FLOAT32_ATOL)
            point = np.array(markers[".position"][frame])
            assert _distance_to_spring(point) <= CAPSULE_RADIUS + 1e-5
            assert _distance_to_link2(point, path[frame, 1]) <= CAPSULE_RADIUS + 1e-5
        else:
            np.testing.assert_allclose(colours[frame], scene.color_scale.rgb(track.tensions[frame]), atol=FLOAT32_ATOL)
            assert max(markers[".scale"][frame]) < 1e-5  # no marker where the spring is clear
    legend = scene.legend_html()
    assert "red: below clearance margin (20 mm)" in legend
    assert "crossing: below the margin in 4 of 7 frames" in legend  # the spring is named
    assert "below clearance margin (20 mm)" in scene.html(animate=False)


def test_a_flagged_spring_is_red_in_every_frame_and_named():
    """The report flags a spring that runs inside its own link (results/own_link.py): red throughout."""
    path = elbow_path([-90, -45, 0])
    result = fixed_design(COLLISION_URDF, [crossing_spring()], path)
    scene = viz.DesignScene(result, path, flagged={"crossing": "runs inside link1 beyond its anchor"})
    assert [scene.rgb(scene.springs[0], frame) for frame in range(3)] == [colors.CLEARANCE_RGB] * 3
    assert "crossing: runs inside link1 beyond its anchor" in scene.legend_html()
    assert '"flag": true' in scene.html(animate=False)  # its name label is red too


def test_clearance_distances_are_those_of_the_clearance_check():
    """Same rule as springbalance.results.clearance: over the same poses, the smallest distance agrees."""
    path = elbow_path(np.linspace(-90, 60, 11))
    result = fixed_design(COLLISION_URDF, [crossing_spring()], path)
    scene = viz.DesignScene(result, path, margin=MARGIN)
    row = result.clearance(margin=MARGIN).row("crossing")
    assert np.min(scene.springs[0].clearance) == pytest.approx(row.distance, abs=1e-9)
    assert int(np.argmin(scene.springs[0].clearance)) == row.sample


def test_margin_defaults_to_the_problems_clearance():
    path = elbow_path([-90, 120])
    design = fixed_design(COLLISION_URDF, [crossing_spring()], path, clearance=sb.Clearance(margin=MARGIN))
    scene = viz.DesignScene(design, path)
    assert scene.margin == MARGIN
    np.testing.assert_array_equal(scene.springs[0].below_margin, [False, True])
    # without a clearance in the problem and without a margin, nothing is checked
    plain = viz.DesignScene(fixed_design(COLLISION_URDF, [crossing_spring()], path), path)
    assert plain.margin is None and plain.springs[0].clearance is None
    assert "clearance" not in plain.legend_html()
    with pytest.raises(sb.InputError, match="margin"):
        viz.DesignScene(design, path, margin=-0.01)


def test_without_collision_geometry_the_scene_is_drawn_by_tension():
    path = elbow_path([-90, 120])  # 120°: crosses link2 on the other URDF
    result = fixed_design(URDF / "two_link_planar.urdf", [crossing_spring()], path)
    scene = viz.DesignScene(result, path, margin=MARGIN)
    track = scene.springs[0]
    assert track.clearance is None and track.below_margin is None
    assert "no collision geometry" in scene.clearance_note
    clip = animation_clips(record_scene(scene))[f"/meshcat/{viz.ROOT}/springs/crossing"]
    colours = next(values for name, values in clip.items() if name.endswith(".material.color"))
    np.testing.assert_allclose(colours, [scene.color_scale.rgb(t) for t in track.tensions])
    assert "clearance" not in scene.legend_html()


def test_no_clearance_entry_when_every_frame_is_clear():
    path = elbow_path([-90, -45, 0])
    scene = viz.DesignScene(fixed_design(COLLISION_URDF, [crossing_spring()], path), path, margin=MARGIN)
    assert np.all(scene.springs[0].clearance > MARGIN)
    assert not scene.clearance_violated and "clearance" not in scene.legend_html()
