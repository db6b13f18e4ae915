r"""One pair of bodies at a time: what of :math:`C_{pq}` the pose sees, and how few springs cancel it.

For the term :math:`\operatorname{tr}(C^T R_p^T R_q)` of a pair (docs/model.md §9.1):

- **Axis parts move to a shorter pair.** Let :math:`a` be the axis (in ``p``'s frame) of the joint
  next to ``p`` on the path to ``q``, and ``n`` the body beyond it. Then :math:`R_p a = R_n a'`, so the
  part :math:`a a^T C` is the term :math:`a' (C^T a)^T` of the pair ``(n, q)`` (a constant when
  ``n = q``); the same at ``q``'s end. What is left, :math:`B = U_p^T C U_q` (2×2, :math:`U` an orthonormal
  basis of the plane normal to each axis), must be cancelled on this pair.
- **Invisible parts.** Some 2×2 blocks :math:`N` give a term that does not depend on the pose (for two
  neighbouring bodies, the "reflections" :math:`\begin{pmatrix}x & y\\ y & -x\end{pmatrix}` in the
  joint's plane): they are found numerically, from the multilinear coefficients of the term over the
  path's joints (:func:`pair_kernels`), and may be added freely.
- **Springs.** A spring between ``p`` and ``q`` adds the rank-one :math:`k D_p D_q^T`. So
  :math:`B + N` for the best invisible :math:`N` needs :func:`fewest_springs` springs: 0, 1 (when
  :math:`\det(B + N) = 0` has a real solution) or 2.
"""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np

from springbalance.design.exact.multilinear import GRID, coefficients_of
from springbalance.design.exact.spatial_tree import Pair, SpatialTree

#: relative size below which a block counts as zero
BLOCK_ZERO = 1e-10


def plane_basis(axis: np.ndarray) -> np.ndarray:
    """3×2: an orthonormal basis of the plane normal to ``axis``, right-handed with it."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    first = helper - (helper @ axis) * axis
    first /= np.linalg.norm(first)
    return np.column_stack([first, np.cross(axis, first)])


def add_pair(pairs: dict[Pair, np.ndarray], u: int, w: int, matrix: np.ndarray) -> None:
    """Add the term ``tr(matrixᵀ R_uᵀ R_w)`` to ``pairs`` (stored with the lower index first; ``u = w``: a constant)."""
    if u == w:
        return
    key, value = ((u, w), matrix) if u < w else ((w, u), matrix.T)
    pairs[key] = pairs.get(key, np.zeros((3, 3))) + value


@dataclasses.dataclass(frozen=True)
class PairPlanes:
    """The planes of a pair ``(p, q)``: ``U_p``, ``U_q`` (3×2) and the two invisible-block bases.

    ``constant``: 2×2 blocks whose term is a constant; ``top``: blocks whose term has no coefficient on every
    joint of the path at once (contains ``constant``).
    """

    left: np.ndarray
    right: np.ndarray
    constant: list[np.ndarray]
    top: list[np.ndarray]


def _null_basis(rows: np.ndarray, scale: float) -> list[np.ndarray]:
    """Orthonormal basis (as 2×2 blocks) of the vectors ``v`` (4) with ``rows @ v = 0``."""
    if rows.size == 0:
        return [block.reshape(2, 2) for block in np.eye(4)]
    _, singular, vt = np.linalg.svd(rows)
    rank = int(np.sum(singular > BLOCK_ZERO * max(scale, 1e-300)))
    return [vt[i].reshape(2, 2) for i in range(rank, 4)]


def pair_kernels(tree: SpatialTree, p: int, q: int) -> PairPlanes:
    """The planes and invisible blocks of the pair ``(p, q)`` (module documentation)."""
    left = plane_basis(tree.neighbour(p, q)[1])
    right = plane_basis(tree.neighbour(q, p)[1])
    joints = sorted(tree.path_joints(p, q))
    values = []
    for angles in itertools.product(GRID, repeat=len(joints)):
        relative = tree.relative_rotation(p, q, dict(zip(joints, angles)))
        values.append((left.T @ relative @ right).ravel())  # basis block E_ab -> u_aᵀ R v_b
    coefficients = np.array([coefficients_of(np.array(values)[:, e], len(joints)).ravel() for e in range(4)]).T
    full = [i for i, index in enumerate(np.ndindex((3,) * len(joints))) if all(index)]
    return PairPlanes(left, right, _null_basis(coefficients[1:], 1.0), _null_basis(coefficients[full], 1.0))


def reduce_pair(tree: SpatialTree, pairs: dict[Pair, np.ndarray], p: int, q: int, planes: PairPlanes) -> np.ndarray:
    """Take the pair ``(p, q)`` out of ``pairs``: its axis parts go to shorter pairs; return ``B`` (2×2) [N·m]."""
    matrix = pairs.pop((p, q), np.zeros((3, 3)))
    near_p, axis_p, beyond_p = tree.neighbour(p, q)
    add_pair(pairs, near_p, q, np.outer(beyond_p, matrix.T @ axis_p))
    matrix = matrix - np.outer(axis_p, axis_p @ matrix)
    near_q, axis_q, beyond_q = tree.neighbour(q, p)
    add_pair(pairs, p, near_q, np.outer(matrix @ axis_q, beyond_q))
    matrix = matrix - np.outer(matrix @ axis_q, axis_q)
    return planes.left.T @ matrix @ planes.right


def _quadratic(block: np.ndarray, basis: list[np.ndarray]) -> tuple[float, np.ndarray, np.ndarray]:
    """``det(B + Σ t_i N_i) = c + gᵀt + tᵀQt``: ``(c, g, Q)``."""
    size = len(basis)

    def det(t: np.ndarray) -> float:
        return float(np.linalg.det(block + sum((ti * n for ti, n in zip(t, basis)), np.zeros((2, 2)))))

    c = det(np.zeros(size))
    eye = np.eye(size)
    g = np.array([(det(eye[i]) - det(-eye[i])) / 2 for i in range(size)])
    quad = np.zeros((size, size))
    for i in range(size):
        quad[i, i] = (det(eye[i]) + det(-eye[i])) / 2 - c
    for i, j in itertools.combinations(range(size), 2):
        quad[i, j] = quad[j, i] = (det(eye[i] + eye[j]) - c - g[i] - g[j] - quad[i, i] - quad[j, j]) / 2
    return c, g, quad


def _root(c: float, g: np.ndarray, quad: np.ndarray, scale: float) -> np.ndarray | None:
    """A ``t`` with ``c + gᵀt + tᵀQt = 0``, or None when there is none."""
    if abs(c) <= BLOCK_ZERO * scale**2:
        return np.zeros(g.size)
    if g.size == 0:
        return None
    values, vectors = np.linalg.eigh(quad)
    along = vectors.T @ g
    tiny = BLOCK_ZERO * max(float(np.max(np.abs(values), initial=0.0)), scale)
    for value, slope, vector in zip(values, along, vectors.T):
        # along an eigenvector: c + slope s + value s²; a real root makes det vanish
        if abs(value) > tiny:
            disc = slope**2 - 4 * value * c
            if disc >= 0:
                return vector * (-slope + np.sqrt(disc)) / (2 * value)
        elif abs(slope) > tiny:
            return vector * (-c / slope)
    curved = np.abs(values) > tiny
    if curved.any() and (np.all(values[curved] > 0) or np.all(values[curved] < 0)):  # the extremum decides
        centre = -0.5 * np.linalg.pinv(quad) @ g
        extremum = c + 0.5 * g @ centre
        if extremum * c <= 0:
            index = int(np.argmax(np.abs(values)))
            return centre + vectors[:, index] * np.sqrt(max(-extremum / values[index], 0.0))
    return None


def fewest_springs(block: np.ndarray, basis: list[np.ndarray], scale: float) -> tuple[int, np.ndarray]:
    """The fewest rank-one terms ``k D_p D_qᵀ`` that cancel ``block`` up to an invisible block, and the block
    they must make (``block + N``)."""
    if np.max(np.abs(block)) <= BLOCK_ZERO * scale:
        return 0, np.zeros((2, 2))
    if basis:
        stacked = np.array([n.ravel() for n in basis]).T
        t = np.linalg.lstsq(stacked, -block.ravel(), rcond=None)[0]
        if np.max(np.abs(block.ravel() + stacked @ t)) <= BLOCK_ZERO * scale:
            return 0, np.zeros((2, 2))
    t_root = _root(*_quadratic(block, basis), scale)
    if t_root is None:
        return 2, block
    return 1, block + sum((ti * n for ti, n in zip(t_root, basis)), np.zeros((2, 2)))
