"""What the arm is and where it works: the mechanism, its workspace samples and their kinematics.

Pinocchio stays numeric here: :class:`Mechanism` is the immutable model, :class:`Workspace`
the sampled poses, and :mod:`~springbalance.model.kinematics` the per-sample numbers
(gravity torque, potential, body placements and Jacobians) computed once.

Importing any module of this package (even the light :mod:`~springbalance.model.budget` and
:mod:`~springbalance.model.robots`) imports these names, and with them numpy and pinocchio.
"""

from __future__ import annotations

from springbalance.model.mechanism import GROUND, Joint, Mechanism
from springbalance.model.workspace import Coupling, Workspace

__all__ = ["GROUND", "Coupling", "Joint", "Mechanism", "Workspace"]
