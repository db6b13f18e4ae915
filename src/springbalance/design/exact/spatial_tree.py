r"""A tree of revolute joints as pair matrices: :math:`V = \text{const} + \sum_{p<q} \operatorname{tr}(C_{pq}^T R_p^T R_q)`.

Body ``j`` is the body moved by Pinocchio joint ``j`` (0 the ground), with frame the joint frame:
:math:`R_j = R_{p(j)} M_j \mathrm{Rot}(a_j, \theta_j)` and :math:`o_j = o_{p(j)} + R_{p(j)} t_j`, where
:math:`(M_j, t_j)` is the joint placement in its parent's frame and :math:`a_j` the axis. A point of
body ``j`` at :math:`z` (joint frame [m]) is :math:`x = o_j + R_j z`, so every point is a sum
:math:`\sum_w R_w v_w` of body-fixed vectors along the path from the ground. Then (docs/model.md §9.1)

- gravity :math:`-\sum_b m_b\, g\cdot x_b` gives :math:`C_{0j} = -g\,\mu_j^T` with the body-fixed first
  moment :math:`\mu_j = m_j c_j + \sum_{k\ \text{child of}\ j} m_{\text{subtree}(k)} t_k` [kg·m];
- a zero-free-length spring from body ``a`` (point :math:`z_a`) to body ``b`` has
  :math:`x_b - x_a = \sum_w R_w D_w` over the bodies ``w`` of the path between them, and
  :math:`k L^2/2` gives :math:`C_{uw} \mathrel{+}= k\,D_u D_w^T` for every pair of them.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from springbalance.design.exact.multilinear import check_revolute
from springbalance.errors import InputError
from springbalance.model.mechanism import GROUND, Mechanism

Pair = tuple[int, int]


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """``Rot(a, θ) = I + sin θ [a]× + (1 − cos θ) [a]×²`` (Rodrigues)."""
    skew = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * skew + (1 - np.cos(angle)) * skew @ skew


@dataclasses.dataclass(frozen=True)
class SpatialTree:
    """A tree of revolute joints read from a mechanism (see the module documentation).

    Attributes:
        mechanism: the arm.
        parents: ``parents[j]`` the parent body of body ``j`` (``parents[0] = -1``).
        rotations: ``M_j`` (N×3×3): joint ``j``'s frame in its parent's at the zero pose.
        offsets: ``t_j`` (N×3) [m]: joint ``j``'s origin in its parent's frame.
        axes: ``a_j`` (N×3): joint ``j``'s unit axis in its own frame.
        moments: ``μ_j`` (N×3) [kg·m]: body-fixed first moments (module documentation).
        gravity: the gravity vector [m/s²].
        names: a body name (URDF link) per body, ``names[0] = "universe"``.
    """

    mechanism: Mechanism
    parents: tuple[int, ...]
    rotations: np.ndarray
    offsets: np.ndarray
    axes: np.ndarray
    moments: np.ndarray
    gravity: np.ndarray
    names: tuple[str, ...]
    _frames: dict  # body name -> (joint, placement of the link frame in the joint frame)

    @classmethod
    def from_mechanism(cls, mechanism: Mechanism) -> SpatialTree:
        """Read the tree; InputError unless every joint is an independent revolute (or continuous) joint."""
        check_revolute(mechanism)
        model = mechanism.model
        size = model.njoints
        data = model.createData()
        pin.computeJointJacobians(model, data, pin.neutral(model))
        axes = np.zeros((size, 3))
        for j in range(1, size):
            jacobian = np.reshape(pin.getJointJacobian(model, data, j, pin.LOCAL), (6, model.nv))
            axes[j] = jacobian[3:, model.joints[j].idx_v]
        parents = tuple([-1] + [int(model.parents[j]) for j in range(1, size)])
        rotations = np.array([np.array(model.jointPlacements[j].rotation) for j in range(size)])
        offsets = np.array([np.array(model.jointPlacements[j].translation) for j in range(size)])
        subtree = np.array([model.inertias[j].mass for j in range(size)])
        moments = np.array([model.inertias[j].mass * np.array(model.inertias[j].lever) for j in range(size)])
        moments[0] = 0.0
        for j in range(size - 1, 0, -1):  # children have larger indices than their parents
            subtree[parents[j]] += subtree[j]
            moments[parents[j]] += subtree[j] * offsets[j]
        frames: dict = {GROUND: (0, pin.SE3.Identity())}
        names = [GROUND] + [model.names[j] for j in range(1, size)]
        for frame in model.frames:
            if frame.type == pin.FrameType.BODY and frame.name not in frames:
                frames[frame.name] = (int(frame.parentJoint), frame.placement)
                if names[frame.parentJoint] == model.names[frame.parentJoint] and frame.parentJoint:
                    names[frame.parentJoint] = frame.name
        return cls(mechanism, parents, rotations, offsets, axes, moments, mechanism.gravity, tuple(names), frames)

    @property
    def size(self) -> int:
        """Bodies, the ground included."""
        return len(self.parents)

    # ---------------------------------------------------------------- paths
    def ancestors(self, body: int) -> list[int]:
        """``body`` and its ancestors down to the ground."""
        chain = [body]
        while chain[-1] != 0:
            chain.append(self.parents[chain[-1]])
        return chain

    def path(self, first: int, second: int) -> list[int]:
        """The bodies from ``first`` to ``second`` through their nearest common ancestor."""
        up_first, up_second = self.ancestors(first), self.ancestors(second)
        common = next(body for body in up_first if body in up_second)
        return up_first[: up_first.index(common) + 1] + up_second[: up_second.index(common)][::-1]

    def path_joints(self, first: int, second: int) -> frozenset[int]:
        """The joints a spring from ``first`` to ``second`` crosses (a joint ``j`` joins body ``j`` to its parent)."""
        path = self.path(first, second)
        return frozenset(w if self.parents[w] == u else u for u, w in zip(path, path[1:]))

    def neighbour(self, end: int, other: int) -> tuple[int, np.ndarray, np.ndarray]:
        r"""The body next to ``end`` on the path to ``other``, the joint axis between them in ``end``'s frame,
        and the same axis in the neighbour's frame: a vector :math:`\lambda a` at ``end`` is the vector
        :math:`\lambda a'` at the neighbour (:math:`R_{end} a = R_{nb} a'`)."""
        path = self.path(end, other)
        near = path[1]
        if self.parents[end] == near:  # the path leaves through end's own joint
            return near, self.axes[end], self.rotations[end] @ self.axes[end]
        return near, self.rotations[near] @ self.axes[near], self.axes[near]  # through a child's joint

    def relative_rotation(self, first: int, second: int, angles: dict[int, float]) -> np.ndarray:
        """``R_first^T R_second`` with joint ``j`` at ``angles[j]`` [rad] (0 where missing)."""

        def absolute(body: int) -> np.ndarray:
            result = np.eye(3)
            for j in self.ancestors(body)[::-1][1:]:
                result = result @ self.rotations[j] @ rotation(self.axes[j], angles.get(j, 0.0))
            return result

        return absolute(first).T @ absolute(second)

    # ---------------------------------------------------------------- points and pair matrices
    def body_index(self, body: str) -> int:
        """The body (joint index) that carries link ``body``."""
        self.mechanism.frame_id(body)  # raises on unknown names
        return int(self._frames[body][0])

    def to_joint_frame(self, body: str, point: np.ndarray) -> np.ndarray:
        """A point of link ``body`` (link frame [m]) in its body's joint frame [m]."""
        return np.array(self._frames[body][1].act(np.asarray(point, dtype=float)))

    def to_link_frame(self, body: str, point: np.ndarray) -> np.ndarray:
        """A point in the joint frame of ``body``'s joint, in link ``body``'s frame [m]."""
        return np.array(self._frames[body][1].actInv(np.asarray(point, dtype=float)))

    def spring_vectors(self, a: int, b: int, z_a: np.ndarray, z_b: np.ndarray) -> dict[int, np.ndarray]:
        r"""``D_w`` [m]: :math:`x_b - x_a = \sum_w R_w D_w` for a spring from body ``a`` (joint-frame point
        ``z_a``) to body ``b``."""
        path = self.path(a, b)
        vectors = {w: np.zeros(3) for w in path}
        vectors[a] = vectors[a] - z_a
        vectors[b] = vectors[b] + z_b
        for u, w in zip(path, path[1:]):
            if self.parents[w] == u:  # going down: o_w = o_u + R_u t_w
                vectors[u] = vectors[u] + self.offsets[w]
            else:  # going up from u to its parent w
                vectors[w] = vectors[w] - self.offsets[u]
        return vectors

    def gravity_pairs(self) -> dict[Pair, np.ndarray]:
        """``C_0j = −g μ_j^T`` [N·m] for every moving body."""
        return {(0, j): -np.outer(self.gravity, self.moments[j]) for j in range(1, self.size)}

    def add_spring(
        self, pairs: dict[Pair, np.ndarray], a: int, b: int, z_a: npt.ArrayLike, z_b: npt.ArrayLike, stiffness: float
    ) -> None:
        """Add ``k D_u D_w^T`` [N·m] of a spring to ``pairs`` (keys ``(u, w)`` with ``u < w``)."""
        vectors = self.spring_vectors(a, b, np.asarray(z_a, float), np.asarray(z_b, float))
        bodies = sorted(vectors)
        for i, u in enumerate(bodies):
            for w in bodies[i + 1 :]:
                pairs[(u, w)] = pairs.get((u, w), np.zeros((3, 3))) + stiffness * np.outer(vectors[u], vectors[w])

    def potential(self, pairs: dict[Pair, np.ndarray], angles: dict[int, float]) -> float:
        r""":math:`\sum_{p<q} \operatorname{tr}(C_{pq}^T R_p^T R_q)` [J] at joint angles ``angles`` [rad]."""
        return float(sum(np.sum(matrix * self.relative_rotation(p, q, angles)) for (p, q), matrix in pairs.items()))


def body_of(tree: SpatialTree, body: str | int) -> int:
    """A body index from a link name or an index."""
    if isinstance(body, (int, np.integer)):
        if not 0 <= int(body) < tree.size:
            raise InputError(f"body index {body} is out of range 0 … {tree.size - 1}")
        return int(body)
    return tree.body_index(body)
