"""A planar serial chain read from a mechanism, as complex numbers (:class:`PlanarChain`), and its
complex stiffness matrix (see :mod:`springbalance.design.exact`)."""

from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model.mechanism import GROUND, Mechanism


@dataclasses.dataclass(frozen=True)
class PlanarChain:
    """A planar serial chain as complex numbers (plane coordinates at the zero pose).

    Attributes:
        mechanism: the :class:`~springbalance.model.mechanism.Mechanism` it was read from.
        bodies: body names, ``bodies[0] = "universe"``, ``bodies[j]`` the link frame moved by joint ``j``.
        offsets: ``l_j`` (n), joint ``j`` → joint ``j+1`` [m] (``offsets[0]`` and the last unused, 0).
        masses: ``m_j`` (n) [kg] (``masses[0] = 0``).
        mass_moments: ``m_j c_j`` (n) [kg·m], centre of mass relative to joint ``j``.
        gravity: planar gravity vector ``γ`` [m/s²].
    """

    mechanism: Mechanism
    bodies: tuple[str, ...]
    offsets: np.ndarray
    masses: np.ndarray
    mass_moments: np.ndarray
    gravity: complex
    _origin: np.ndarray  # world point of joint 1's axis (plane origin) [m]
    _basis: np.ndarray  # rows u, v, n: plane axes and the joint axis (world)
    _joint_points: np.ndarray  # complex O_j(0) (n), O_0 = 0
    _joint_of_frame: dict[str, int]

    @property
    def size(self) -> int:
        """``n``: number of bodies, ground included."""
        return len(self.bodies)

    @classmethod
    def from_mechanism(cls, mechanism: Mechanism) -> PlanarChain:
        """Read a planar serial chain from a mechanism.

        Needs revolute (or continuous) joints in series (each joint's parent is the previous
        one), all about parallel axes, and no mimic joints; otherwise raises
        :class:`~springbalance.errors.InputError` naming the culprit.
        """
        model = mechanism.model
        _check_serial_chain(mechanism)
        data = model.createData()
        q = mechanism.configurations(np.zeros((1, mechanism.nv)))[0]
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        basis = _plane_basis(model, data)
        u, v = basis[0], basis[1]
        origin = np.array(data.oMi[1].translation)

        def plane(point: np.ndarray) -> complex:
            relative = basis @ (np.asarray(point) - origin)
            return complex(relative[0], relative[1])

        n = model.njoints
        joint_points = np.array([0j] + [plane(data.oMi[j].translation) for j in range(1, n)])
        offsets = np.zeros(n, dtype=complex)
        offsets[1 : n - 1] = joint_points[2:] - joint_points[1 : n - 1]
        masses = np.zeros(n)
        moments = np.zeros(n, dtype=complex)
        for j in range(1, n):
            inertia = model.inertias[j]
            masses[j] = inertia.mass
            moments[j] = inertia.mass * (plane(data.oMi[j].act(inertia.lever)) - joint_points[j])
        gravity_world = np.asarray(mechanism.gravity)
        gravity = complex(gravity_world @ u, gravity_world @ v)
        bodies, joint_of_frame = _chain_bodies(model)
        return cls(
            mechanism, tuple(bodies), offsets, masses, moments, gravity, origin, basis, joint_points, joint_of_frame
        )

    # ---------------------------------------------------------------- bodies and points
    def body_index(self, body: str) -> int:
        """Index ``j`` of the chain body that carries link frame ``body`` (0 for the ground)."""
        self.mechanism.frame_id(body)  # raises on unknown names
        return self._joint_of_frame[body]

    def _frame(self, body: str) -> pin.SE3:
        model = self.mechanism.model
        data = model.createData()
        pin.framesForwardKinematics(model, data, self.mechanism.configurations(np.zeros((1, self.mechanism.nv)))[0])
        return data.oMf[self.mechanism.frame_id(body)]

    def to_plane(self, body: str, point: npt.ArrayLike) -> complex:
        """Plane coordinate ``z`` [m] of the body-frame point ``point`` relative to the body's joint."""
        placement = self._frame(body)
        world = placement.act(np.asarray(point, dtype=float))
        relative = self._basis @ (world - self._origin)
        return complex(relative[0], relative[1]) - self._joint_points[self.body_index(body)]

    def to_body(self, body: str, z: complex) -> np.ndarray:
        """Body-frame point [m] (in the plane of the body frame's origin) of plane coordinate ``z``."""
        placement = self._frame(body)
        planar = z + self._joint_points[self.body_index(body)]
        height = self._basis[2] @ (np.array(placement.translation) - self._origin)
        world = self._origin + planar.real * self._basis[0] + planar.imag * self._basis[1] + height * self._basis[2]
        return np.array(placement.actInv(world))

    # ---------------------------------------------------------------- blocks
    def gravity_blocks(self) -> np.ndarray:
        r"""Gravity part of :math:`K_{0j}`: :math:`-\bar\gamma (m_j c_j + l_j \sum_{b>j} m_b)` (n) [N·m]."""
        beyond = np.concatenate([np.cumsum(self.masses[::-1])[::-1][1:], [0.0]])  # Σ_{b>j} m_b [kg]
        return -np.conj(self.gravity) * (self.mass_moments + self.offsets * beyond)

    def spring_vector(self, a: int, b: int, z_a: complex, z_b: complex) -> np.ndarray:
        """``D`` (n): ``x_b - x_a = Σ_j D_j w_j`` for a spring from body ``a`` to body ``b`` (a < b) [m]."""
        vector = np.zeros(self.size, dtype=complex)
        vector[max(a, 1) : b] = self.offsets[max(a, 1) : b]
        vector[a] -= z_a
        vector[b] += z_b
        return vector

    def blocks(self, springs: Sequence[tuple]) -> np.ndarray:
        """Complex stiffness matrix ``K`` (n×n, upper triangle used) [N·m] for springs
        given as ``(a, b, z_a, z_b, k)`` with body indices and plane coordinates."""
        matrix = np.zeros((self.size, self.size), dtype=complex)
        matrix[0, :] += self.gravity_blocks()
        for a, b, z_a, z_b, stiffness in springs:
            vector = self.spring_vector(a, b, z_a, z_b)
            matrix += stiffness * np.outer(np.conj(vector), vector)  # [N/m]·[m²]
        return matrix

    def __repr__(self) -> str:
        return f"PlanarChain({self.mechanism.name!r}, bodies={list(self.bodies)})"


def require_independent_revolute(
    mechanism: Mechanism, analysis: str, mimic_needs: str, prismatic_why: str = ""
) -> None:
    """InputError naming the culprit unless every joint is an independent revolute (or continuous) joint:
    no mimic joint (``the {analysis} needs {mimic_needs}``), no prismatic joint."""
    if mechanism.model.njoints - 1 != mechanism.nv:
        raise InputError(f"mechanism {mechanism.name!r} has mimic joints; the {analysis} needs {mimic_needs}")
    for joint in mechanism.joints:
        if joint.kind == "prismatic":
            raise InputError(f"joint {joint.name!r} is prismatic; the {analysis} needs revolute joints{prismatic_why}")


def _check_serial_chain(mechanism: Mechanism) -> None:
    """InputError naming the culprit unless the mechanism is a serial chain of independent revolute joints."""
    model = mechanism.model
    require_independent_revolute(
        mechanism, "planar exact-balance analysis", "a serial chain of independent joints (use the optimiser)"
    )
    for joint_id in range(1, model.njoints):
        if model.parents[joint_id] != joint_id - 1:
            raise InputError(
                f"joint {model.names[joint_id]!r} does not follow joint {model.names[joint_id - 1]!r}: "
                "the planar exact-balance analysis needs a serial chain"
            )


def _plane_basis(model: pin.Model, data: pin.Data) -> np.ndarray:
    """Rows ``u, v, n`` (world): the plane axes and the joint axis, ``(u, v, n)`` right-handed; InputError
    when a joint is not parallel to the first (``data``: joint Jacobians computed at the zero pose)."""
    axes = []
    for joint_id in range(1, model.njoints):
        jacobian = np.reshape(pin.getJointJacobian(model, data, joint_id, pin.LOCAL_WORLD_ALIGNED), (6, model.nv))
        axes.append(np.array(jacobian[3:, model.joints[joint_id].idx_v]))
    normal = axes[0] / np.linalg.norm(axes[0])
    for joint_id, axis in enumerate(axes, start=1):
        if np.linalg.norm(np.cross(axis, normal)) > 1e-9:
            raise InputError(
                f"joint {model.names[joint_id]!r} is not parallel to joint {model.names[1]!r}: the chain is not planar"
            )
    helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = helper - (helper @ normal) * normal
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)  # (u, v, n) right-handed: positive rotation about n turns u towards v
    return np.array([u, v, normal])


def _chain_bodies(model: pin.Model) -> tuple[list[str], dict[str, int]]:
    """The chain's body names (``bodies[j]``: the first link frame moved by joint ``j``, else the joint's name)
    and the joint index of every body frame."""
    bodies = [GROUND]
    joint_of_frame = {GROUND: 0}
    for frame in model.frames:
        if frame.type == pin.FrameType.BODY:
            joint_of_frame.setdefault(frame.name, int(frame.parentJoint))
    for j in range(1, model.njoints):
        names = [name for name, joint in joint_of_frame.items() if joint == j]
        bodies.append(names[0] if names else model.names[j])
    return bodies, joint_of_frame


def as_chain(target: PlanarChain | Mechanism) -> PlanarChain:
    """``target`` itself when it is a :class:`PlanarChain`, else the chain read from the mechanism."""
    return target if isinstance(target, PlanarChain) else PlanarChain.from_mechanism(target)
