"""What the arm is and where it works: the mechanism, its workspace samples and their kinematics.

Pinocchio stays numeric here: :class:`Mechanism` is the immutable model, :class:`Workspace`
the sampled poses, and :mod:`~springbalance.model.kinematics` the per-sample numbers
(gravity torque, potential, body placements and Jacobians) computed once.

The names below are imported on first use (``from springbalance.model import Mechanism``), so
that the light modules of this package (:mod:`~springbalance.model.budget`,
:mod:`~springbalance.model.robots`) load without pinocchio.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from springbalance.model.mechanism import GROUND, Joint, Mechanism
    from springbalance.model.workspace import Coupling, Workspace

__all__ = ["GROUND", "Coupling", "Joint", "Mechanism", "Workspace"]

_SOURCES = {"GROUND": "mechanism", "Joint": "mechanism", "Mechanism": "mechanism",
            "Coupling": "workspace", "Workspace": "workspace"}


def __getattr__(name: str):
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_SOURCES[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
