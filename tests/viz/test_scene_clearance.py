"""Springs that fit the arm: in the frames where a spring is below the clearance margin it is magenta."""

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
    """The clearance colour must not read as a tension (or compression) or as the arm: its hue is more
    than twice the census tolerance (14°) from every colour of the scale and from link1's blue."""
    for colour in browser.scale_colours(401) + [LINK1_RGB]:
        assert hue_distance(colors.CLEARANCE_RGB, colour) > 2 * 14, colour
    r, g, b = colors.CLEARANCE_RGB
    assert colorsys.rgb_to_hsv(r, g, b)[1] > 0.9  # a saturated colour, not grey
    assert f"#{colors.CLEARANCE_COLOR:06x}" in colors.ColorScale(10).legend_html(clearance_margin=0.012)


def test_spring_is_magenta_where_it_passes_through_link2():
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
    # what meshcat receives: the colour track is magenta in the crossing frames, the tension colour elsewhere
    recorder = record_scene(scene)
    helix = umsgpack.unpackb(recorder.tree["meshcat"][viz.ROOT]["springs"]["crossing"].object)["object"]
    assert helix["materials"][0]["color"] == scene.color_scale.hex(track.tensions[0])  # frame 0 is clear
    clip = animation_clips(recorder)[f"/meshcat/{viz.ROOT}/springs/crossing"]
    colours = next(values for name, values in clip.items() if name.endswith(".material.color"))
    for frame, crosses in enumerate(crossing):
        if crosses:
            np.testing.assert_allclose(colours[frame], colors.CLEARANCE_RGB)
        else:
            np.testing.assert_allclose(colours[frame], scene.color_scale.rgb(track.tensions[frame]))
            assert hue_distance(colours[frame], colors.CLEARANCE_RGB) > 28
    legend = scene.legend_html()
    assert "below clearance margin (20 mm)" in legend and "magenta" in legend
    assert "below clearance margin (20 mm)" in scene.html(animate=False)


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
