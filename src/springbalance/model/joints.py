"""The degrees of freedom of a mechanism: its one-DOF joints (revolute, continuous, prismatic).

Mimic joints follow their primary joint and are not degrees of freedom. Units: joint coordinates in rad
(revolute, continuous) or m (prismatic); generalised forces in N·m or N.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin

from springbalance.errors import InputError

_REVOLUTE = {"JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned"}
_CONTINUOUS = {"JointModelRUBX", "JointModelRUBY", "JointModelRUBZ", "JointModelRevoluteUnboundedUnaligned"}
_PRISMATIC = {"JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned"}


@dataclasses.dataclass(frozen=True)
class Joint:
    """One degree of freedom of the mechanism.

    Attributes:
        name: URDF joint name.
        kind: ``"revolute"``, ``"continuous"`` or ``"prismatic"``.
        index_q: first index in Pinocchio's configuration vector (two slots, cos and sin,
            for a continuous joint).
        index_v: index in the velocity/torque vector.
        lower, upper: range from the URDF [rad or m]; ``[-pi, pi]`` for continuous joints.
    """

    name: str
    kind: str
    index_q: int
    index_v: int
    lower: float
    upper: float

    @property
    def unit(self) -> str:
        """Unit of the joint coordinate."""
        return "m" if self.kind == "prismatic" else "rad"

    @property
    def torque_unit(self) -> str:
        """Unit of the generalised force on this joint."""
        return "N" if self.kind == "prismatic" else "N·m"


def degrees_of_freedom(model: pin.Model) -> list[Joint]:
    """The one-DOF joints of ``model`` in velocity order, with their ranges (the URDF's, or ±π rad, ±1 m)."""
    joints = []
    for joint_id in range(1, model.njoints):
        joint_model = model.joints[joint_id]
        kind_name = joint_model.shortname()
        name = model.names[joint_id]
        if "Mimic" in kind_name or joint_model.nv == 0:
            continue
        if kind_name in _REVOLUTE:
            kind = "revolute"
        elif kind_name in _CONTINUOUS:
            kind = "continuous"
        elif kind_name in _PRISMATIC:
            kind = "prismatic"
        else:
            raise InputError(
                f"joint {name!r} is a {kind_name}; springbalance supports revolute, continuous and prismatic joints"
            )
        iq, iv = joint_model.idx_q, joint_model.idx_v
        if kind == "continuous":
            lower, upper = -np.pi, np.pi
        else:
            lower, upper = float(model.lowerPositionLimit[iq]), float(model.upperPositionLimit[iq])
            if not (np.isfinite(lower) and np.isfinite(upper)) or lower >= upper:
                lower, upper = (-np.pi, np.pi) if kind == "revolute" else (-1.0, 1.0)
        joints.append(Joint(name, kind, iq, iv, lower, upper))
    return sorted(joints, key=lambda joint: joint.index_v)
