"""The brackets of a scene: a grey rod from each anchor that stands off its link to the link's nearest surface
point, moving with the link (:mod:`springbalance.viz.rods`).

The arm is urdf/two_link_planar_collision.urdf: link1's collision box is 0.5 × 0.04 × 0.04 m centred 0.25 m along
link1's x axis (top face at z = 0.02 m); the shoulder turns about (0, -1, 0), so at a shoulder angle θ link1's
x axis is (cos θ, 0, sin θ) and its z axis (−sin θ, 0, cos θ). The anchor (0.3, 0, 0.12) on link1 stands 0.1 m
above the top face; its bracket's foot is (0.3, 0, 0.02), worked out from the box alone.
"""

from __future__ import annotations

import numpy as np

import springbalance as sb
from scene_helpers import COLLISION_URDF, FLOAT32_ATOL, URDF, animation_clips, fixed_design, record_scene
from springbalance.viz import scene as viz

ANCHOR, FOOT = np.array([0.3, 0.0, 0.12]), np.array([0.3, 0.0, 0.02])  # [m], link1's frame


def _world(point: np.ndarray, shoulder: float) -> np.ndarray:
    along, up = np.array([np.cos(shoulder), 0, np.sin(shoulder)]), np.array([-np.sin(shoulder), 0, np.cos(shoulder)])
    return point[0] * along + point[2] * up


def _springs():
    return [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", [0.3, 0, 0.5]), sb.Anchor("link1", ANCHOR), "far", stiffness=200.0
        )
    ]


def test_a_bracket_holds_the_anchor_off_its_link_in_every_frame():
    shoulder = np.radians([0.0, 30.0, 60.0])
    path = np.column_stack([shoulder, np.zeros(3)])
    scene = viz.DesignScene(fixed_design(COLLISION_URDF, _springs(), path), path)
    (track,) = scene.springs
    assert set(track.brackets) == {"b"}  # the ground anchor (a) has none
    feet = np.array([_world(FOOT, angle) for angle in shoulder])
    np.testing.assert_allclose(track.brackets["b"], feet, atol=1e-9)
    np.testing.assert_allclose(track.points_by_end()["b"], [_world(ANCHOR, angle) for angle in shoulder], atol=1e-9)

    recorder = record_scene(scene)
    node = recorder.tree["meshcat"][viz.ROOT]["brackets"]["far.b"]
    assert node.object is not None  # drawn: a cylinder
    clip = animation_clips(recorder)[f"/meshcat/{viz.ROOT}/brackets/far.b"]
    # the rod sits at the middle of foot and anchor, 0.1 m long (its y scale), in every frame
    middles = (feet + np.array([_world(ANCHOR, angle) for angle in shoulder])) / 2
    np.testing.assert_allclose(clip[".position"], middles, atol=FLOAT32_ATOL)
    np.testing.assert_allclose(np.array(clip[".scale"])[:, 1], 0.1, atol=1e-6)


def test_no_bracket_without_collision_geometry():
    path = np.array([[0.0, 0.0], [0.5, 0.0]])
    scene = viz.DesignScene(fixed_design(URDF / "two_link_planar.urdf", _springs(), path), path)
    assert scene.springs[0].brackets is None
    assert "brackets" not in record_scene(scene).tree["meshcat"][viz.ROOT]  # a defaultdict: no such child


def test_a_bracket_is_red_in_the_frames_where_it_passes_through_another_link():
    """link2's anchor 0.3 m behind the elbow along link2's axis: its bracket runs from link2's end face at the
    elbow back along the arm. At elbow 0 it lies on link1's axis inside link1's box; at elbow 2 rad and 90° it
    points away from link1, touching only its end face at the elbow."""
    from springbalance.viz import colors

    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0.3, 0, 0.5]), sb.Anchor("link2", [-0.3, 0, 0]), "behind", stiffness=100.0
    )
    path = np.array([[0.0, 2.0], [0.0, 0.0], [0.0, np.pi / 2]])
    scene = viz.DesignScene(fixed_design(COLLISION_URDF, [spring], path), path)
    (track,) = scene.springs
    np.testing.assert_array_equal(track.brackets_through["b"], [False, True, False])
    clip = animation_clips(record_scene(scene))[f"/meshcat/{viz.ROOT}/brackets/behind.b"]
    colours = next(values for name, values in clip.items() if name.endswith(".material.color"))
    grey = np.array([0x8C, 0x90, 0x99]) / 255
    np.testing.assert_allclose(colours, [grey, colors.CLEARANCE_RGB, grey], atol=FLOAT32_ATOL)
    assert scene.problems() == ["behind.b's bracket: through a link in 1 of 3 frames"]  # the legend's red entries


def test_a_bracket_through_a_link_at_the_first_pose_is_drawn_red_from_the_start():
    import umsgpack

    from springbalance.viz import colors

    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0.3, 0, 0.5]), sb.Anchor("link2", [-0.3, 0, 0]), "behind", stiffness=100.0
    )
    for path, colour in ((np.array([[0.0, 0.0]]), colors.CLEARANCE_COLOR), (np.array([[0.0, 2.0]]), 0x8C9099)):
        scene = viz.DesignScene(fixed_design(COLLISION_URDF, [spring], path), path)  # one pose: no animation
        node = record_scene(scene).tree["meshcat"][viz.ROOT]["brackets"]["behind.b"]
        assert umsgpack.unpackb(node.object)["object"]["materials"][0]["color"] == colour
