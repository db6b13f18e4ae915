"""The numbers the pose slider shows (:class:`PoseData`): per pose of a scene's path, the joint coordinates,
each spring's force and each joint's residual torque, as the JSON a scene page embeds.

For pose ``i`` of the path (joint values ``q_i``) and the design's evaluation on the path
(:meth:`~springbalance.design.evaluated.EvaluatedDesign.evaluate_on`, the same numbers the scene's colours
come from):

- ``q[i][j]``: joint ``j``'s coordinate, in degrees for a revolute or continuous joint, in mm for a
  prismatic one (the units people read);
- ``force[i][s]``: spring ``s``'s generalised force, its tension ``F(L)`` [N] (negative when it pushes)
  for a two-point spring, its force along its direction [N] for a directed one, its torque [N·m] for a
  torsional one;
- ``length[i][s]``: a two-point spring's length ``L`` [mm] (a directed spring's stroke ``s`` [mm], a
  torsional spring's joint angle [deg]);
- ``tau[i][j]``: the residual actuator torque ``τ_j(q_i) = g_j(q_i) − Σ_s τ_{s,j}(q_i)`` [N·m or N]
  that the actuator still has to give (gravity less the springs' torques, docs/model.md §2);
- ``gravity[i][j]``: the unbalanced gravity torque ``g_j(q_i)`` [N·m or N], for comparison.

Numbers are rounded to :data:`DIGITS` significant digits (the page shows four). Frame ``i`` of the scene's
animation is at time ``i / fps`` [s].
"""

from __future__ import annotations

import dataclasses
import json
import math
from typing import Any, Protocol

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.problem import Evaluation
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import TwoPointSpring
from springbalance.springs.laws.directed import DirectedSpring

#: significant digits of the embedded numbers
DIGITS = 6


def _round(values: np.ndarray) -> list:
    """``values`` as nested lists of floats rounded to :data:`DIGITS` significant digits (non-finite: None)."""
    array = np.asarray(values, dtype=float)
    if array.ndim > 1:
        return [_round(row) for row in array]
    return [float(f"{value:.{DIGITS}g}") if math.isfinite(value) else None for value in array.tolist()]


@dataclasses.dataclass
class PoseData:
    """The per-pose numbers of a scene (see the module documentation for the units).

    Attributes:
        fps: frames per second of the scene's animation (frame ``i`` at ``i / fps`` s).
        joints: per joint ``{"name", "unit", "torque_unit"}`` (coordinate unit ``deg`` or ``mm``).
        springs: per spring ``{"name", "type", "force_unit", "length_unit"}``.
        q, tau, gravity: N×nv; force, length: N×S (nested lists, rounded).
        title: what the poses are (the slider's caption), e.g. ``"sweep of each joint"``.
    """

    fps: float
    joints: list[dict[str, str]]
    springs: list[dict[str, str]]
    q: list
    tau: list
    gravity: list
    force: list
    length: list
    title: str = "poses"

    @property
    def size(self) -> int:
        """Number of poses."""
        return len(self.q)

    def to_dict(self) -> dict[str, Any]:
        """The JSON-able dictionary the page embeds."""
        return dataclasses.asdict(self)

    def to_json(self) -> str:
        """:meth:`to_dict` as JSON that is safe inside an HTML ``<script>`` element (``</`` escaped)."""
        return json.dumps(self.to_dict(), separators=(",", ":"), allow_nan=False).replace("</", "<\\/")


def pose_data(
    design: EvaluatedDesign, workspace: Workspace, evaluation: Evaluation, fps: float, title: str = "poses"
) -> PoseData:
    """The :class:`PoseData` of ``design`` along the poses of ``workspace`` (N poses), from ``evaluation``
    (the design evaluated on that workspace: ``tau`` N×nv, ``tensions`` and ``lengths`` N×S)."""
    mechanism = design.problem.mechanism
    joints, scales = [], []
    for joint in mechanism.joints:
        prismatic = joint.kind == "prismatic"
        joints.append({"name": joint.name, "unit": "mm" if prismatic else "deg", "torque_unit": joint.torque_unit})
        scales.append(1e3 if prismatic else 180.0 / math.pi)
    springs, length_scales = [], []
    for spring, record in zip(design.problem.springs, design.springs):
        # a tension along a length, or a force along a stroke; else a torque at a joint angle
        linear = isinstance(spring, (TwoPointSpring, DirectedSpring))
        springs.append(
            {
                "name": str(record["name"]),
                "type": str(record["type"]),
                "force_unit": "N" if linear else "N·m",
                "length_unit": "mm" if linear else "deg",
            }
        )
        length_scales.append(1e3 if linear else 180.0 / math.pi)
    kinematics = workspace.kinematics()
    return PoseData(
        fps=float(fps),
        joints=joints,
        springs=springs,
        q=_round(workspace.joint_values * np.array(scales)),
        tau=_round(evaluation.tau),
        gravity=_round(kinematics.gravity_torque),
        force=_round(evaluation.tensions),
        length=_round(evaluation.lengths * np.array(length_scales)),
        title=title,
    )


class SceneLike(Protocol):
    """What :func:`scene_pose_data` reads of a scene (:class:`~springbalance.viz.design_scene.DesignScene`)."""

    design: EvaluatedDesign
    workspace: Workspace
    evaluation: Evaluation
    fps: int
    path_title: str


def scene_pose_data(scene: SceneLike) -> PoseData:
    """The :class:`PoseData` of a :class:`~springbalance.viz.design_scene.DesignScene`: its design along its
    path of poses, from the evaluation its colours come from, captioned with its ``path_title``."""
    return pose_data(scene.design, scene.workspace, scene.evaluation, scene.fps, scene.path_title)
