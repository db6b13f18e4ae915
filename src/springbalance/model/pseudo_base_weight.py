r"""What a pseudo-base's own weight costs the actuators before any spring is fitted.

A pseudo-base ``pb_<J>`` (:mod:`springbalance.model.pseudo_bases`) of mass :math:`m` [kg] with its centre of
mass at :math:`c` [m] in its frame weighs at :math:`x = t_{pb} + R_{pb}\,c` (:math:`R_{pb} = I`, or a turn
about the world's z axis for one that keeps only the vertical), so its gravity torque is
:math:`\tau = -m\,J^T \gamma` [N·m or N], :math:`J` (3×nv) the Jacobian of that point and :math:`\gamma` the
gravity vector [m/s²]: the weight of a point mass at joint :math:`J`'s origin.
"""

from __future__ import annotations

import numpy as np

from springbalance.model.kinematics import WorkspaceKinematics

__all__ = ["pseudo_base_torques"]


def pseudo_base_torques(kinematics: WorkspaceKinematics) -> dict[str, np.ndarray]:
    """Per pseudo-base body ``pb_<J>`` of the workspace's mechanism, its gravity torque over the samples (N×nv)."""
    mechanism = kinematics.mechanism
    gravity = mechanism.gravity
    torques = {}
    for base in mechanism.pseudo_bases:
        jacobian = kinematics.body(base.body).point_jacobians(np.asarray(base.com, dtype=float))  # N×3×nv
        torques[base.body] = -base.mass * np.einsum("nkv,k->nv", jacobian, gravity)
    return torques
