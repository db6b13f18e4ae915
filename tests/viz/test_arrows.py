"""Forces along a fixed direction in the scene: an arrow at the anchor along the push (viz/arrows.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

import springbalance as sb
from scene_helpers import animation_clips, recorded_scene
from springbalance.viz import scene as viz
from springbalance.viz.arrows import ARROW_LENGTH

URDF = Path(__file__).resolve().parents[2] / "urdf" / "structure_ii.urdf"


def _design():
    mechanism = sb.Mechanism.from_urdf(URDF, mimic=True, gravity=9.81)
    workspace = sb.Workspace.grid(mechanism, 5)
    springs = [
        sb.DirectedForce(sb.Anchor("link1", [0.1, 0, 0]), name="f1", direction=[0, 0, 1], force=120.0),
        sb.DirectedForce(sb.Anchor("crank2", [0.1, 0, 0]), name="f2", direction=[0, 0, -1], force=-40.0),
    ]
    return sb.DesignResult(sb.DesignProblem(mechanism, workspace, springs), np.zeros(0))


def test_each_directed_force_is_an_arrow_from_its_anchor_along_its_push():
    design = _design()
    mechanism = design.problem.mechanism
    path = np.array([[0.3, -0.5], [-1.0, 1.2], [0.0, 0.0]])
    scene = viz.DesignScene(design, path)
    assert [arrow.name for arrow in scene.arrows] == ["f1", "f2"] and scene.skipped == [] and scene.springs == []
    data = mechanism.model.createData()
    for frame, q in enumerate(scene.configurations):
        pin.framesForwardKinematics(mechanism.model, data, q)
        for arrow, body in zip(scene.arrows, ("link1", "crank2")):
            anchor = data.oMf[mechanism.model.getFrameId(body)].act(np.array([0.1, 0, 0]))
            np.testing.assert_allclose(arrow.starts[frame], anchor, atol=1e-12)
            # both push the anchor up: f1 = 120 N along +z; f2 = -40 N along -z
            np.testing.assert_allclose(arrow.directions[frame], [0, 0, 1], atol=1e-12)
            tip = arrow.transform(frame) @ [0, ARROW_LENGTH, 0, 1]  # the local y axis, scaled by the force
            np.testing.assert_allclose(tip[:3], anchor + [0, 0, ARROW_LENGTH * arrow.scales()[frame]], atol=1e-12)
            rotation = arrow.rigid_transform(frame)[:3, :3]
            np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
            assert np.linalg.det(rotation) > 0
    assert np.allclose(scene.arrows[1].forces, -40.0) and np.all(scene.arrows[1].scales() == 1.0)  # its own largest
    _, recorder = recorded_scene(design, path)
    arrows = recorder.tree["meshcat"][viz.ROOT]["arrows"]
    for name in ("f1", "f2"):
        assert arrows[name]["shaft"].object is not None and arrows[name]["head"].object is not None
    clips = animation_clips(recorder)
    assert any(key.endswith("arrows/f2") for key in clips)  # the arrows move with the arm


def test_a_scene_of_arrows_only_has_no_tension_scale_in_its_legend():
    """Structure II's two forces are arrows, no helix: the legend names them instead of a tension scale."""
    design = _design()
    legend = viz.DesignScene(design, design.problem.workspace.joint_values[:3]).legend_html()
    assert "spring tension" not in legend and "force along a fixed direction: f1, f2" in legend
    assert 'id="springbalance-legend"' in legend  # the overlay's labels and the censuses keep off it
