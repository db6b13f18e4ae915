"""Numeric cache of a workspace: what Pinocchio computes once per sample.

For every sample ``q_i`` of a :class:`~springbalance.model.workspace.Workspace`:

- ``gravity_torque[i] = g(q_i)`` [N·m or N] from ``computeGeneralizedGravity``: the joint
  torque that holds the bare mechanism still, ``g = ∂V_g/∂q``;
- ``potential[i] = V_g(q_i)`` [J] from ``computePotentialEnergy``;
- for every body ``B`` that carries a spring end (on request): its placement
  ``(R_B, t_B)`` and its 6×nv frame Jacobian ``J_B`` in ``LOCAL_WORLD_ALIGNED``
  (linear rows first), see docs/model.md §1–2.

Nothing here depends on the design; the optimiser reads these arrays as parameters.
"""

from __future__ import annotations

import dataclasses
from typing import Iterable, Protocol, Sequence

import numpy as np
import pinocchio as pin

from springbalance.model.mechanism import Mechanism


class Samples(Protocol):
    """What the kinematics read of a workspace (:class:`~springbalance.model.workspace.Workspace`):
    its mechanism and its Pinocchio configurations (N×nq)."""

    mechanism: Mechanism

    @property
    def configurations(self) -> np.ndarray:
        """The Pinocchio configurations (N×nq)."""


@dataclasses.dataclass(frozen=True)
class BodyKinematics:
    """Placement and Jacobian of one body over the N samples.

    Attributes:
        translation: N×3 origin of the body frame in world [m].
        rotation: N×3×3 body-to-world rotation.
        jacobian: N×6×nv frame Jacobian, LOCAL_WORLD_ALIGNED, linear rows first
            [m/rad, 1/rad].
    """

    translation: np.ndarray
    rotation: np.ndarray
    jacobian: np.ndarray

    def points(self, local_points: np.ndarray) -> np.ndarray:
        """World positions N×3 of a point (3,) or per-sample points (N×3) fixed in the body [m]."""
        local_points = np.asarray(local_points, dtype=float)
        if local_points.ndim == 1:
            return self.translation + self.rotation @ local_points
        return self.translation + np.einsum("nij,nj->ni", self.rotation, local_points)

    def point_jacobians(self, local_points: np.ndarray) -> np.ndarray:
        """N×3×nv Jacobians of a body-fixed point: ``J_p = J[:3] - skew(R p) J[3:]``."""
        lever = self.points(local_points) - self.translation  # R p, N×3 [m]
        angular = self.jacobian[:, 3:, :]
        return self.jacobian[:, :3, :] - np.cross(lever[:, :, None], angular, axis=1)


def gravity_and_potential(model: pin.Model, configurations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``g(q_i)`` (N×nv) [N·m or N] and ``V_g(q_i)`` (N) [J] of ``model`` at the configurations (N×nq).

    ``g`` comes from one batched call (``rneaInParallel`` with zero velocity and acceleration, a C++
    loop over the samples); a model with mimic joints, which that call does not handle, takes
    ``computeGeneralizedGravity`` sample by sample. ``V_g = -M g·c`` with ``M`` the mass of the moving
    bodies and ``c`` their centre of mass (``centerOfMass``: one C++ call per sample), the same as
    ``-Σ_j m_j g·c_j`` over the moving bodies (``computePotentialEnergy`` rejects mimic joints).
    """
    configurations = np.asarray(configurations, dtype=float)
    n = configurations.shape[0]
    data = model.createData()
    if n and not len(model.mimicking_joints) and hasattr(pin, "rneaInParallel"):
        gravity_torque = np.zeros((model.nv, n), order="F")
        zero = np.zeros((model.nv, n), order="F")
        pin.rneaInParallel(1, pin.ModelPool(model, 1), np.asfortranarray(configurations.T), zero, zero, gravity_torque)
        gravity_torque = np.ascontiguousarray(gravity_torque.T)
    else:
        gravity_torque = np.array([pin.computeGeneralizedGravity(model, data, q) for q in configurations]).reshape(
            n, model.nv
        )
    centres = np.array([pin.centerOfMass(model, data, q, False) for q in configurations]).reshape(n, 3)
    potential = -data.mass[0] * (centres @ np.array(model.gravity.linear)) if n else np.zeros(0)
    return gravity_torque, potential


class WorkspaceKinematics:
    """Gravity, potential energy and body kinematics of a workspace, computed once."""

    def __init__(self, workspace: Samples):
        self.workspace = workspace
        self.mechanism = workspace.mechanism
        model = self.mechanism.model
        configurations = workspace.configurations
        self.gravity_torque, self.potential = gravity_and_potential(model, configurations)
        self._bodies: dict[str, BodyKinematics] = {}

    def body(self, name: str) -> BodyKinematics:
        """Kinematics of body ``name`` (computed on first request)."""
        if name not in self._bodies:
            self.prepare([name])
        return self._bodies[name]

    def prepare(self, names: Iterable[str]) -> None:
        """Compute placements and Jacobians of every body in ``names`` in one pass."""
        missing = [name for name in dict.fromkeys(names) if name not in self._bodies]
        if not missing:
            return
        mechanism, model = self.mechanism, self.mechanism.model
        frame_ids = [mechanism.frame_id(name) for name in missing]
        configurations = self.workspace.configurations
        n, nv = configurations.shape[0], model.nv
        translations = np.zeros((len(missing), n, 3))
        rotations = np.zeros((len(missing), n, 3, 3))
        jacobians = np.zeros((len(missing), n, 6, nv))
        data = model.createData()
        for i, q in enumerate(configurations):
            pin.computeJointJacobians(model, data, q)  # also runs forward kinematics
            pin.updateFramePlacements(model, data)
            for slot, frame_id in enumerate(frame_ids):
                placement = data.oMf[frame_id]
                translations[slot, i] = placement.translation
                rotations[slot, i] = placement.rotation
                jacobians[slot, i] = np.reshape(
                    pin.getFrameJacobian(model, data, frame_id, pin.LOCAL_WORLD_ALIGNED), (6, nv)
                )
        for slot, name in enumerate(missing):
            self._bodies[name] = BodyKinematics(translations[slot], rotations[slot], jacobians[slot])


class StackedKinematics(WorkspaceKinematics):
    """The kinematics of a workspace repeated once per scenario (see :mod:`springbalance.design.scenarios`).

    A :class:`WorkspaceKinematics` of the stacked workspace (the same attributes and methods); it computes
    its own arrays from ``base`` (it does not run the base class's constructor).

    Block ``s`` (rows ``s·N … (s+1)·N - 1``) holds the gravity torque and potential of
    ``mechanisms[s]`` (same joints and bodies, other masses); body placements and Jacobians
    are the base workspace's, repeated, because masses do not change kinematics.

    Attributes:
        n_blocks: number of scenarios ``S``; ``block_size``: samples per scenario ``N``.
    """

    def __init__(self, workspace: Samples, base: WorkspaceKinematics, mechanisms: Sequence[Mechanism]):
        self.workspace = workspace
        self.mechanism = base.mechanism
        self.base = base
        self.n_blocks = len(mechanisms)
        self.block_size = base.gravity_torque.shape[0]
        configurations = base.workspace.configurations
        blocks = [gravity_and_potential(mechanism.model, configurations) for mechanism in mechanisms]
        self.gravity_torque = np.vstack([torque for torque, _ in blocks])
        self.potential = np.concatenate([potential for _, potential in blocks])
        self._bodies: dict[str, BodyKinematics] = {}

    def body(self, name: str) -> BodyKinematics:
        """Kinematics of body ``name``: the base workspace's, repeated per scenario (computed on first request)."""
        if name not in self._bodies:
            single = self.base.body(name)
            repeat = (self.n_blocks,) + (1,) * (single.translation.ndim - 1)
            self._bodies[name] = BodyKinematics(
                np.tile(single.translation, repeat),
                np.tile(single.rotation, (self.n_blocks, 1, 1)),
                np.tile(single.jacobian, (self.n_blocks, 1, 1)),
            )
        return self._bodies[name]

    def prepare(self, names: Iterable[str]) -> None:
        """Compute the base workspace's placements and Jacobians of ``names`` (repeated per scenario on use)."""
        self.base.prepare(names)
