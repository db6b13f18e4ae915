r"""Which poses a scene animates and its pose slider scrubs through (:func:`scene_poses`).

- ``"sweep"`` (the default): each moving joint swept in turn over its workspace range
  (:func:`springbalance.model.sweeps.animation_path`);
- ``"workspace"``: the design's own workspace samples, in their order (a grid is a raster path);
- ``"worst"`` or ``"worst:N"``: the ``N`` (default :data:`WORST_COUNT`) workspace samples where the residual
  torque is largest, worst first, ranked by the weighted norm
  :math:`\lVert w \circ \tau(q_i) \rVert_2 = \sqrt{\sum_j (w_j \tau_j(q_i))^2}` [N·m] with the
  problem's joint weights ``w`` (the quantity the ``rms`` objective averages).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.errors import InputError
from springbalance.model import sweeps

#: the kinds of pose path a scene can show
POSE_PATHS = ("sweep", "workspace", "worst")
#: poses of ``"worst"`` when no count is given
WORST_COUNT = 12


def parse_poses(spec: str) -> tuple[str, int | None]:
    """``"sweep"``, ``"workspace"``, ``"worst"`` or ``"worst:N"`` (N ≥ 1) as (kind, count or None).

    Raises:
        InputError: any other text (the message names it and the valid forms).
    """
    kind, _, count = str(spec).strip().partition(":")
    valid = "sweep, workspace, worst or worst:N (N ≥ 1)"
    if kind not in POSE_PATHS or (count and kind != "worst"):
        raise InputError(f"poses {spec!r}: expected {valid}")
    if not count:
        return kind, None
    if not count.isdigit() or int(count) < 1:
        raise InputError(f"poses {spec!r}: the count after 'worst:' must be an integer ≥ 1 ({valid})")
    return kind, int(count)


def worst_poses(design: EvaluatedDesign, count: int = WORST_COUNT) -> np.ndarray:
    """Indices of the ``count`` samples of the design's workspace with the largest weighted residual torque
    norm (see the module documentation), worst first (ties: the earlier sample first)."""
    problem = design.problem
    tau = design.evaluate_on(problem.workspace).tau  # N×nv [N·m or N], on the base workspace
    norm = np.sqrt(np.sum((tau * problem.weights) ** 2, axis=1))
    order = np.argsort(-norm, kind="stable")
    return order[: max(int(count), 1)]


def scene_poses(design: EvaluatedDesign, poses: str = "sweep", frames_per_joint: int = 48) -> tuple[np.ndarray, str]:
    """The joint values (N×nv) [rad or m] of the scene's path for ``poses`` (:func:`parse_poses`) and its
    caption for the pose slider."""
    kind, count = parse_poses(poses)
    if kind == "sweep":
        return sweeps.animation_path(design, frames_per_joint), "sweep of each joint"
    workspace = design.problem.workspace
    if kind == "workspace":
        return workspace.joint_values.copy(), f"the design's {workspace.size} workspace poses"
    chosen = worst_poses(design, WORST_COUNT if count is None else count)
    return workspace.joint_values[chosen], f"the {len(chosen)} worst poses (largest residual torque first)"


def scene_path(
    design: EvaluatedDesign, joint_values: npt.ArrayLike | None, poses: str | None, frames_per_joint: int = 48
) -> tuple[npt.ArrayLike | None, str]:
    """A scene's path and its caption: ``joint_values`` as given (None: the scene sweeps each joint) with the
    caption "poses" (or "sweep of each joint"), or, for ``poses`` and no ``joint_values``, :func:`scene_poses`."""
    if poses is not None and joint_values is None:
        return scene_poses(design, poses, frames_per_joint)
    return joint_values, "sweep of each joint" if joint_values is None else "poses"
