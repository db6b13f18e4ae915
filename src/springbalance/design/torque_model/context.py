"""What a spring element sees of one workspace sample (:class:`SampleContext`): CasADi symbols of the
sample data column, with body-fixed points as :class:`PointKinematics` (docs/model.md §2)."""

from __future__ import annotations

import casadi as ca
import numpy as np


class SampleContext:
    """What a spring element sees of one sample (CasADi symbols of the data column).

    ``point(body, p)`` → :class:`PointKinematics` of the body-fixed point ``p``;
    ``coordinate(joint)`` → the joint coordinate ``q_i`` [rad or m];
    ``direction(joint)`` → the unit torque vector ``e_i`` (nv); ``zero()`` → nv zeros;
    ``gravity`` → the gravity vector (3) [m/s²].
    """

    def __init__(
        self, nv: int, gravity: np.ndarray, bodies: dict, ground: dict, coordinates: dict, joint_index: dict
    ) -> None:
        self.nv = nv
        self.gravity = ca.DM(np.asarray(gravity, dtype=float).reshape(3, 1))
        self._bodies, self._ground, self._coordinates, self._joint_index = bodies, ground, coordinates, joint_index

    def point(self, body: str, local: ca.SX | ca.DM) -> PointKinematics:
        if body in self._bodies:
            t, R, J = self._bodies[body]
            lever = ca.mtimes(R, local)  # R p, world-aligned [m]
            return PointKinematics(t + lever, lever, J, self.nv)
        t0, R0 = self._ground[body]
        return PointKinematics(ca.DM(t0) + ca.mtimes(ca.DM(R0), local), None, None, self.nv)

    def coordinate(self, joint: str) -> ca.SX:
        return self._coordinates[joint]

    def direction(self, joint: str) -> ca.DM:
        unit = np.zeros(self.nv)
        unit[self._joint_index[joint]] = 1.0
        return ca.DM(unit)

    def zero(self) -> ca.DM:
        return ca.DM.zeros(self.nv, 1)


class PointKinematics:
    """A body-fixed point at one sample: world ``position`` and the map ``f -> J_p^T f``."""

    def __init__(self, position: ca.SX, lever: ca.SX | None, jacobian: ca.SX | None, nv: int) -> None:
        self.position, self._lever, self._jacobian, self._nv = position, lever, jacobian, nv

    def generalized(self, force: ca.SX) -> ca.SX | ca.DM:
        """``J_p^T f`` (nv): the joint torques of a force ``f`` [N] applied at the point (0 on the ground)."""
        if self._jacobian is None:
            return ca.DM.zeros(self._nv, 1)
        J = self._jacobian
        assert self._lever is not None  # a moving point has its lever with its Jacobian
        return ca.mtimes(J[:3, :].T, force) + ca.mtimes(J[3:, :].T, ca.cross(self._lever, force))
