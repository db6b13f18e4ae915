r"""Spatial exact balance by construction (:func:`synthesize_spatial`) and proofs that a topology cannot
reach it (:func:`spatial_reachability`); docs/model.md §9.1.

**Construction.** Take the pairs of bodies from the longest path to the shortest. At pair ``(p, q)``
move the axis parts of :math:`C_{pq}` to shorter pairs, and cancel what is left with
:func:`~springbalance.design.exact.spatial_blocks.fewest_springs` springs between ``p`` and ``q``: split the
block by SVD, :math:`-(B + N) = \sum_r \sigma_r u_r v_r^T`, and give spring ``r`` the vectors
:math:`D_p = \alpha U_p u_r`, :math:`D_q = \beta U_q v_r` with :math:`k\alpha\beta = \sigma_r` (anchors from
:meth:`~springbalance.design.exact.spatial_tree.SpatialTree.spring_vectors`). A spring changes only the
pairs on its own path, all shorter, so the pairs already done stay cancelled: the arm ends exactly
balanced with at most two springs per pair. The result is checked by the exact test
(:func:`~springbalance.design.exact.multilinear.spatial_coefficients`, from Pinocchio).

**Proofs** for a topology (a list of body pairs):

1. *Support.* A spring's potential depends only on the joints of its path, so a non-zero gravity
   coefficient on joints that no spring's path covers can never be cancelled.
2. *Rank.* For a spring pair whose path no other spring's path contains, only gravity reaches its
   full-path coefficients; they need :func:`~springbalance.design.exact.spatial_blocks.fewest_springs`
   springs on that very pair, whatever the anchors and stiffnesses.
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np

from springbalance.design.exact.multilinear import SpatialCoefficients, spatial_coefficients
from springbalance.design.exact.spatial_blocks import fewest_springs, pair_kernels, reduce_pair
from springbalance.design.exact.spatial_tree import Pair, SpatialTree, body_of
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws import ZeroFreeLengthSpring
from springbalance.springs.params import Anchor

#: a synthesised design counts as exact when its coefficients are below this fraction of gravity's
SYNTHESIS_TOLERANCE = 1e-9


@dataclasses.dataclass
class SpatialSynthesis:
    """Outcome of :func:`synthesize_spatial`.

    Attributes:
        springs: fixed zero-free-length springs (anchors in the link frames) [m, N/m].
        pairs: body-name pair → the number of springs it got.
        coefficients: the exact test of the design (Pinocchio).
        missing: pairs the construction needed but the allowed pairs exclude (empty when complete).
    """

    springs: list[ZeroFreeLengthSpring]
    pairs: dict[tuple[str, str], int]
    coefficients: SpatialCoefficients
    missing: list[tuple[str, str]]

    @property
    def exact(self) -> bool:
        return not self.missing and self.coefficients.relative <= SYNTHESIS_TOLERANCE

    def describe(self) -> str:
        if self.missing:
            names = ", ".join(f"{a}–{b}" for a, b in self.missing)
            return f"the construction needs springs on pairs the topology lacks: {names}"
        return (
            f"{len(self.springs)} springs on {len(self.pairs)} pairs; largest coefficient left "
            f"{self.coefficients.relative:.3g} of gravity's"
        )


def _pairs_longest_first(tree: SpatialTree) -> list[Pair]:
    pairs = [(p, q) for p in range(tree.size) for q in range(p + 1, tree.size)]
    return sorted(pairs, key=lambda pair: -len(tree.path(*pair)))


def synthesize_spatial(
    mechanism: Mechanism,
    allowed: Sequence[tuple[str, str]] | None = None,
    stiffness: float | None = None,
    reach: float = 0.1,
) -> SpatialSynthesis:
    r"""Springs that balance a revolute chain or tree exactly (module documentation).

    ``allowed``: body pairs that may carry springs (None: every pair); ``stiffness`` [N/m] of every spring,
    or None to choose each one's so that its vectors :math:`|D_p|\,|D_q| =` ``reach``² [m²]. How that product
    splits between the two ends puts the anchors as near their joints as it can (:func:`_spring`).
    """
    if stiffness is not None and not (np.isfinite(stiffness) and stiffness > 0):
        raise InputError(f"stiffness must be a number > 0 [N/m], got {stiffness!r}")
    if not (np.isfinite(reach) and reach > 0):
        raise InputError(f"reach must be a length > 0 [m], got {reach!r}")
    tree = SpatialTree.from_mechanism(mechanism)
    permitted = None if allowed is None else {tuple(sorted((body_of(tree, a), body_of(tree, b)))) for a, b in allowed}
    pairs = tree.gravity_pairs()
    scale = max(float(np.max(np.abs(matrix))) for matrix in pairs.values())
    springs: list[ZeroFreeLengthSpring] = []
    counts: dict[tuple[str, str], int] = {}
    missing = []
    for p, q in _pairs_longest_first(tree):
        if (p, q) not in pairs:
            continue
        planes = pair_kernels(tree, p, q)
        count, target = fewest_springs(reduce_pair(tree, pairs, p, q, planes), planes.constant, scale)
        if count == 0:
            continue
        names = (tree.names[p], tree.names[q])
        if permitted is not None and (p, q) not in permitted:
            missing.append(names)
            continue
        u, sigma, vt = np.linalg.svd(-target)
        for r in range(count):
            k = stiffness if stiffness is not None else sigma[r] / reach**2
            directions = (planes.left @ u[:, r], planes.right @ vt[r])
            springs.append(_spring(tree, pairs, (p, q), directions, sigma[r] / k, k, f"zfl{len(springs) + 1}"))
        counts[names] = count
        pairs.pop((p, q), None)  # what the springs leave on their own pair is invisible (a constant)
    return SpatialSynthesis(springs, counts, spatial_coefficients(mechanism, springs), missing)


def _spring(
    tree: SpatialTree, pairs: dict[Pair, np.ndarray], ends: Pair, directions: tuple, product: float, k: float, name: str
) -> ZeroFreeLengthSpring:
    r"""The spring from ``p`` to ``q`` with :math:`D_p = \alpha u`, :math:`D_q = \beta v`, :math:`\alpha\beta =`
    ``product`` [m²]; its terms are added to ``pairs``.

    The split is free: :math:`\alpha` minimises :math:`|z_p|^2 + |z_q|^2` (the anchors nearest their joints),
    :math:`z_p = o_p - \alpha u`, :math:`z_q = (c/\alpha) v - o_q`, a real root of
    :math:`\alpha^4 - (u\cdot o_p)\alpha^3 + c (v\cdot o_q)\alpha - c^2 = 0` (:math:`o` the path's offsets).
    """
    (p, q), (u, v) = ends, directions
    offsets = tree.spring_vectors(p, q, np.zeros(3), np.zeros(3))
    roots = np.roots([1.0, -(u @ offsets[p]), 0.0, product * (v @ offsets[q]), -(product**2)])
    real = [float(root.real) for root in roots if abs(root.imag) <= 1e-9 * max(abs(root), 1e-300)]

    def ends_of(alpha: float) -> tuple[np.ndarray, np.ndarray]:  # D_p = −z_p + offset, D_q = z_q + offset
        return offsets[p] - alpha * u, product / alpha * v - offsets[q]

    alpha = min(real, key=lambda a: sum(float(z @ z) for z in ends_of(a)))
    z_p, z_q = ends_of(alpha)
    tree.add_spring(pairs, p, q, z_p, z_q, k)
    anchors = [Anchor(tree.names[body], tree.to_link_frame(tree.names[body], z)) for body, z in ((p, z_p), (q, z_q))]
    return ZeroFreeLengthSpring(anchors[0], anchors[1], name=name, stiffness=float(k))


@dataclasses.dataclass(frozen=True)
class SpatialVerdict:
    """Whether a topology is proven unable to balance exactly, and why (``reason`` empty when not proven)."""

    unreachable: bool
    reason: str


class SpatialReachability:
    """The proofs of the module documentation for one arm, reused over many topologies."""

    def __init__(self, mechanism: Mechanism):
        self.tree = tree = SpatialTree.from_mechanism(mechanism)
        gravity = spatial_coefficients(mechanism, []).gravity
        limit = 1e-9 * max(float(np.max(np.abs(gravity.ravel()[1:]))), 1e-300)
        self.supports = {
            frozenset(j + 1 for j, a in enumerate(index) if a)
            for index in zip(*np.nonzero(np.abs(gravity) > limit))
            if any(index)
        }
        pairs = tree.gravity_pairs()
        scale = max(float(np.max(np.abs(matrix))) for matrix in pairs.values())
        self.needed: dict[Pair, int] = {}
        self.sound = True  # the rank proof needs every invisible block to be a constant
        for p, q in _pairs_longest_first(tree):
            planes = pair_kernels(tree, p, q)
            self.sound &= len(planes.top) == len(planes.constant)
            self.needed[(p, q)] = fewest_springs(reduce_pair(tree, pairs, p, q, planes), planes.top, scale)[0]

    def verdict(self, topology: Sequence[tuple[str, str]]) -> SpatialVerdict:
        """The proofs for springs on the body pairs ``topology`` (names or body indices)."""
        tree = self.tree
        ends = [tuple(sorted((body_of(tree, a), body_of(tree, b)))) for a, b in topology]
        paths = [tree.path_joints(*end) for end in ends]
        joint_names = tree.mechanism.joint_names
        for support in sorted(self.supports, key=len, reverse=True):
            if not any(support <= path for path in paths):
                named = ", ".join(joint_names[j - 1] for j in sorted(support))
                return SpatialVerdict(True, f"gravity's coefficient on joints {named} is reached by no spring")
        if self.sound:
            for end, path in zip(ends, paths):
                if any(path < other for other in paths):
                    continue  # another spring's path contains this one's
                have = ends.count(end)
                need = self.needed[end]  # type: ignore[index]
                if need > have:
                    names = f"{tree.names[end[0]]}–{tree.names[end[1]]}"
                    return SpatialVerdict(
                        True, f"gravity's block on the outermost pair {names} needs {need} springs there, it has {have}"
                    )
        return SpatialVerdict(False, "")


def spatial_reachability(mechanism: Mechanism, topology: Sequence[tuple[str, str]]) -> SpatialVerdict:
    """Whether springs on the body pairs ``topology`` are proven unable to balance the arm exactly."""
    return SpatialReachability(mechanism).verdict(topology)
