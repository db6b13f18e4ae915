"""The parallelograms of the pseudo-bases in the scene (issue 29): rods that form true parallelograms whose
cranks stay world-vertical, drawn and animated with the arm."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import springbalance as sb
from scene_helpers import animation_clips, recorded_scene
from springbalance.design.problem import DesignProblem
from springbalance.results.result import DesignResult
from springbalance.viz.parallelograms import CRANK, parallelogram_rods

ROOT = Path(__file__).resolve().parents[2]
TWO_LINK = ROOT / "urdf" / "two_link_planar.urdf"


def _design():
    mechanism = sb.Mechanism.from_urdf(TWO_LINK, pseudo_bases=["elbow"])
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("pb_elbow", [0, 0, 0.2]), sb.Anchor("link2", [0.1, 0, 0]), "s", stiffness=196.2
    )
    poses = np.column_stack([np.linspace(-1.0, 1.0, 6), np.linspace(1.5, -1.5, 6)])
    return DesignResult(DesignProblem(mechanism, sb.Workspace.from_array(mechanism, poses), [spring]), np.zeros(0))


def test_rods_form_a_parallelogram_on_link1_with_vertical_cranks():
    design = _design()
    path = np.column_stack([np.linspace(-1.2, 1.2, 5), np.linspace(2.0, -2.0, 5)])
    scene, recorder = recorded_scene(design, path)
    rods = scene.parallelograms["pb_elbow"]
    assert rods.shape == (5, 3, 2, 3)  # shoulder → elbow: one parallelogram, three rods of its own
    for (theta, _), (bar, crank_a, crank_b) in zip(path, rods):
        # link1 (0.5 m along x, turning about -y) from the shoulder at the origin to the elbow
        elbow = 0.5 * np.array([np.cos(theta), 0.0, np.sin(theta)])
        up = np.array([0.0, 0.0, CRANK])
        np.testing.assert_allclose(bar, [up, elbow + up], atol=1e-12)
        np.testing.assert_allclose(crank_a, [np.zeros(3), up], atol=1e-12)
        np.testing.assert_allclose(crank_b, [elbow, elbow + up], atol=1e-12)
    clips = animation_clips(recorder)
    animated = [name for name in clips if "parallelograms/pb_elbow/rod" in name]
    assert len(animated) == 3


def test_a_vertical_pseudo_base_needs_no_parallelogram_across_the_vertical_yaw():
    """KR-like arm: a1 turns about the vertical, so pb_a3 keeping only the vertical needs one parallelogram (over
    link2, a2 → a3: three rods), where keeping the orientation it needs two (a1 → a2 and a2 → a3: six rods)."""
    kr = ROOT / "urdf" / "kr_like_6r.urdf"
    q = np.zeros((1, 6))
    for keep, rods in (("orientation", 6), ("vertical", 3)):
        mechanism = sb.Mechanism.from_urdf(kr, pseudo_bases=[{"joint": "a3", "keep": keep}])
        track = parallelogram_rods(mechanism, mechanism.configurations(q))["pb_a3"]
        assert track.shape == (1, rods, 2, 3)
    # at zero pose a2's origin is 0.15 m out and 0.6 m up (0.4 + 0.2), a3's 0.6 m further out along link2 (x)
    np.testing.assert_allclose(track[0, 0], [[0.15, 0, 0.6 + CRANK], [0.75, 0, 0.6 + CRANK]], atol=1e-12)
