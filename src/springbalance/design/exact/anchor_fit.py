r"""Anchors and stiffnesses in boxes that balance a spatial arm exactly: a local fit on the exact coefficients.

With zero-free-length springs the exact-balance conditions are the non-constant multilinear coefficients
of the potential (:mod:`~springbalance.design.exact.multilinear`, docs/model.md §9.1):

.. math:: r(z, k) = T' \Bigl(V_g + \sum_s \tfrac12 k_s \bigl|x_{b,s}(z_{b,s}) - x_{a,s}(z_{a,s})\bigr|^2\Bigr) = 0,

``V`` on the grid :math:`\{0, 2\pi/3, 4\pi/3\}^n` [J] and :math:`T'` the grid-to-coefficient map without its
constant row (the Kronecker product of the 3×3 inverse per joint). With the anchors fixed :math:`r` is linear
in :math:`k` (:mod:`~springbalance.design.exact.stiffness_fit`); with them free it is cubic. A spring at
anchors :math:`z_a`, :math:`z_b` (link frames [m]) has :math:`d = p_b + R_b z_b - p_a - R_a z_a` on the grid, and

.. math:: \partial V_s / \partial z_b = k R_b^T d,\quad \partial V_s / \partial z_a = -k R_a^T d,\quad
    \partial V_s / \partial k = \tfrac12 |d|^2 .

:class:`CoefficientSystem` holds the grid kinematics of an arm, projected on the (small) space of
coefficients that gravity and springs can reach at all (an orthonormal basis of the span of
:math:`T'` applied to every product of body positions and rotation columns), so one residual costs a few
hundred numbers however large :math:`3^n`. (Run many fits under ``threadpoolctl.threadpool_limits(1)``, as
the study's screen does: on matrices this small BLAS threads only contend.) :func:`fit_anchors` draws anchor sets uniformly in the boxes
(deterministic seed), fits :math:`k \ge 0` by non-negative least squares, then refines anchors and
stiffnesses together by bounded least squares (``scipy.optimize.least_squares``, trust-region reflective),
the anchors kept in their boxes and :math:`k` in its bounds. It returns the best draw: its relative residual
(the largest non-constant coefficient over gravity's largest) is 0 for an exact design. A positive residual
is a design *not found*, not a proof (the proofs are :class:`~springbalance.design.exact.SpatialReachability`).
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np

from springbalance.design.exact.multilinear import INVERSE, grid_kinematics
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws import ZeroFreeLengthSpring
from springbalance.springs.params import Anchor

#: most joints the fit takes (the coefficient map is 3^n × 3^n)
MAX_JOINTS = 7
#: relative singular value below which a direction of the coefficient space counts as unreachable
RANK_TOLERANCE = 1e-12

Box = tuple[Sequence[float], Sequence[float]]


@dataclasses.dataclass(frozen=True)
class SpringEnds:
    """One spring to fit: body ``a`` to body ``b``, each end free in a box of its link frame [m]."""

    a: str
    box_a: Box
    b: str
    box_b: Box


@dataclasses.dataclass
class AnchorFit:
    """Outcome of :func:`fit_anchors`.

    Attributes:
        relative: largest non-constant coefficient left over gravity's largest (0: exact balance).
        anchors: per spring, its two anchors (link frames [m]).
        stiffness: per spring, ``k`` [N/m].
        draws: anchor sets tried.
    """

    relative: float
    anchors: list[tuple[np.ndarray, np.ndarray]]
    stiffness: np.ndarray
    draws: int

    def springs(self, ends: Sequence[SpringEnds], names: Sequence[str] | None = None) -> list[ZeroFreeLengthSpring]:
        """The fitted springs as fixed zero-free-length springs."""
        names = names or [f"zfl{i + 1}" for i in range(len(ends))]
        return [
            ZeroFreeLengthSpring(Anchor(end.a, tuple(za)), Anchor(end.b, tuple(zb)), name=name, stiffness=float(k))
            for end, (za, zb), k, name in zip(ends, self.anchors, self.stiffness, names)
        ]


def _one_body_per_joint(mechanism: Mechanism) -> list[str]:
    """A link per joint (the ground first): links welded to one joint move as one body."""
    chosen: dict[int, str] = {}
    for name in mechanism.body_names:
        joint = 0 if mechanism.is_ground(name) else int(mechanism.model.frames[mechanism.frame_id(name)].parentJoint)
        chosen.setdefault(joint, name)
    return [chosen[joint] for joint in sorted(chosen)]


def _coefficient_map(joints: int) -> np.ndarray:
    """``T'``: grid values (C order) → the non-constant coefficients (rows), exact (module documentation)."""
    transform = np.ones((1, 1))
    for _ in range(joints):
        transform = np.kron(transform, INVERSE)
    return transform[1:]


class CoefficientSystem:
    """The grid kinematics of an arm and its reachable coefficient space (module documentation)."""

    def __init__(self, mechanism: Mechanism):
        if mechanism.nv > MAX_JOINTS:
            raise InputError(
                f"mechanism {mechanism.name!r} has {mechanism.nv} joints; the anchor fit takes at most {MAX_JOINTS}"
            )
        self.mechanism = mechanism
        self.kinematics = kinematics = grid_kinematics(mechanism)
        self._placements: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self._pairs: dict[tuple[str, str], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = {}
        transform = _coefficient_map(mechanism.nv)
        gravity = transform @ np.asarray(kinematics.potential, dtype=float)
        self.scale = float(np.max(np.abs(gravity))) if gravity.size else 0.0
        if not self.scale > 0:
            raise InputError(f"gravity does not load mechanism {mechanism.name!r}: nothing to balance")
        features = [np.asarray(kinematics.potential, dtype=float)[:, None]]
        bodies = [self._placement(name) for name in _one_body_per_joint(mechanism)]  # welded links span the same
        for i, (p_u, r_u) in enumerate(bodies):
            for p_w, r_w in bodies[i:]:
                features += [np.sum(p_u * p_w, axis=1)[:, None], np.einsum("ni,nij->nj", p_u, r_w)]
                features += [np.einsum("nij,ni->nj", r_u, p_w), np.einsum("nki,nkj->nij", r_u, r_w).reshape(-1, 9)]
        from threadpoolctl import threadpool_limits  # BLAS threads only slow these small matrices down

        with threadpool_limits(limits=1):
            basis, singular, _ = np.linalg.svd(transform @ np.hstack(features), full_matrices=False)
        rank = int(np.sum(singular > RANK_TOLERANCE * singular[0]))
        #: the projection on the reachable coefficients, and with it the full map for the final check
        self.projection = basis[:, :rank].T @ transform
        self.transform = transform
        self.gravity = self.projection @ np.asarray(kinematics.potential, dtype=float)

    def _placement(self, body: str) -> tuple[np.ndarray, np.ndarray]:
        """Position (N×3) [m] and rotation (N×3×3) of a link frame on the grid (the ground: 0 and I)."""
        if body not in self._placements:
            if self.mechanism.is_ground(body):
                size = self.kinematics.potential.shape[0]
                self._placements[body] = (np.zeros((size, 3)), np.broadcast_to(np.eye(3), (size, 3, 3)))
            else:
                kinematics = self.kinematics.body(body)
                self._placements[body] = (kinematics.translation, kinematics.rotation)
        return self._placements[body]

    def pair_terms(self, a: str, b: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        r"""The projected coefficients of :math:`|d|^2` for a spring from link ``a`` to link ``b``:
        :math:`|d|^2 = |\Delta|^2 + 2\Delta^T R_b z_b - 2\Delta^T R_a z_a - 2 z_a^T R_a^T R_b z_b + \text{const}`,
        :math:`\Delta = p_b - p_a`; returns ``(P|Δ|², P Δᵀ R_a, P Δᵀ R_b, P R_aᵀ R_b)`` (r, r×3, r×3, r×3×3)."""
        key = (a, b)
        if key not in self._pairs:
            (p_a, r_a), (p_b, r_b) = self._placement(a), self._placement(b)
            delta = p_b - p_a
            self._pairs[key] = (
                self.projection @ np.sum(delta * delta, axis=1),
                self.projection @ np.einsum("ni,nij->nj", delta, r_a),
                self.projection @ np.einsum("ni,nij->nj", delta, r_b),
                (self.projection @ np.einsum("nki,nkj->nij", r_a, r_b).reshape(-1, 9)).reshape(-1, 3, 3),
            )
        return self._pairs[key]

    def relative(self, ends: Sequence[SpringEnds], anchors: np.ndarray, stiffness: np.ndarray) -> float:
        """Largest non-constant coefficient over gravity's largest, on the full coefficient map (not projected)."""
        total = np.asarray(self.kinematics.potential, dtype=float).copy()
        for end, (z_a, z_b), k in zip(ends, anchors, stiffness):
            (p_a, r_a), (p_b, r_b) = self._placement(end.a), self._placement(end.b)
            d = p_b + r_b @ z_b - p_a - r_a @ z_a
            total += 0.5 * k * np.sum(d * d, axis=1)
        return float(np.max(np.abs(self.transform @ total))) / self.scale


def _residual_and_jacobian(
    system: CoefficientSystem, ends: Sequence[SpringEnds], x: np.ndarray, k_scale: float
) -> tuple[np.ndarray, np.ndarray]:
    """``r`` / gravity's scale and its Jacobian for ``x`` = per spring ``(z_a, z_b, k / k_scale)``."""
    blocks = x.reshape(len(ends), 7)
    residual = system.gravity.copy()
    jacobian = np.zeros((residual.size, x.size))
    for s, end in enumerate(ends):
        square, lever_a, lever_b, cross = system.pair_terms(end.a, end.b)
        z_a, z_b, k = blocks[s, :3], blocks[s, 3:6], blocks[s, 6] * k_scale
        length = square + 2 * lever_b @ z_b - 2 * lever_a @ z_a - 2 * np.einsum("rij,i,j->r", cross, z_a, z_b)
        residual += 0.5 * k * length
        jacobian[:, 7 * s : 7 * s + 3] = -k * (lever_a + cross @ z_b)
        jacobian[:, 7 * s + 3 : 7 * s + 6] = k * (lever_b - np.einsum("rij,i->rj", cross, z_a))
        jacobian[:, 7 * s + 6] = 0.5 * k_scale * length
    return residual / system.scale, jacobian / system.scale


def _nnls_stiffness(system: CoefficientSystem, ends: Sequence[SpringEnds], anchors: np.ndarray) -> np.ndarray:
    """The best ``k ≥ 0`` [N/m] for fixed anchors (non-negative least squares, as in ``fit_stiffnesses``)."""
    from scipy.optimize import nnls  # scipy.optimize stays out of start-up (tests/test_package.py)

    rows = []
    for end, (z_a, z_b) in zip(ends, anchors):
        square, lever_a, lever_b, cross = system.pair_terms(end.a, end.b)
        rows.append(0.5 * square + lever_b @ z_b - lever_a @ z_a - np.einsum("rij,i,j->r", cross, z_a, z_b))
    columns = np.array(rows)  # one row per spring: the coefficients of |d|²/2 [m²]
    scale = np.maximum(np.max(np.abs(columns), axis=1), 1e-300)
    scaled, _ = nnls((columns / scale[:, None]).T, -system.gravity, maxiter=50 * len(ends))
    return np.asarray(scaled / scale)


def _refine(
    system: CoefficientSystem,
    ends: Sequence[SpringEnds],
    anchors: np.ndarray,
    box: tuple[np.ndarray, np.ndarray],
    stiffness: tuple[float, float],
    max_evaluations: int,
    k_start: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Anchors ``(m, 2, 3)`` [m] and stiffnesses [N/m] refined from ``anchors`` (and ``k_start``, or k from NNLS)
    by bounded least squares on the projected coefficients."""
    from scipy.optimize import least_squares  # scipy.optimize stays out of start-up

    m = len(ends)
    # a spring the NNLS leaves at k = 0 has no gradient in its anchors: start it where its coefficients are
    # gravity's size instead, k = scale / (half-diagonal of one box × of the other)
    half = [
        np.linalg.norm(np.subtract(e.box_a[1], e.box_a[0])) * np.linalg.norm(np.subtract(e.box_b[1], e.box_b[0])) / 4
        for e in ends
    ]
    typical = np.array([system.scale / max(h, 1e-6) for h in half])
    k = _nnls_stiffness(system, ends, anchors) if k_start is None else np.asarray(k_start, dtype=float)
    k = np.clip(np.where(k > 0, k, typical), *stiffness)
    k_scale = max(float(np.max(k)), 1.0)
    start = np.hstack([anchors.reshape(m, 6), (k / k_scale)[:, None]]).ravel()
    bounds = (
        np.hstack([box[0], np.full((m, 1), stiffness[0] / k_scale)]).ravel(),
        np.hstack([box[1], np.full((m, 1), stiffness[1] / k_scale)]).ravel(),
    )
    cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def both(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # residual and Jacobian from one evaluation
        key = x.tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = _residual_and_jacobian(system, ends, x, k_scale)
        return cache[key]

    solution = least_squares(
        lambda x: both(x)[0],
        np.clip(start, *bounds),
        jac=lambda x: both(x)[1],
        bounds=bounds,
        method="trf",
        x_scale="jac",
        ftol=1e-12,
        xtol=1e-12,
        gtol=1e-12,
        max_nfev=max_evaluations,
    )
    blocks = solution.x.reshape(m, 7)
    return blocks[:, :6].reshape(m, 2, 3), blocks[:, 6] * k_scale


def fit_anchors(
    system: CoefficientSystem,
    ends: Sequence[SpringEnds],
    stiffness: tuple[float, float] = (0.0, np.inf),
    draws: int = 4,
    seed: int | Sequence[int] = 0,
    target: float = 1e-12,
    max_evaluations: int = 100,
    start: AnchorFit | None = None,
) -> AnchorFit:
    """The best of ``draws`` local fits of anchors (in their boxes) and stiffnesses (in ``stiffness`` [N/m]) to
    exact balance (module documentation); it stops at the first draw whose relative residual is below ``target``.
    ``max_evaluations`` bounds the residual evaluations of one draw; ``start`` (a fit of the same springs) is
    the first draw instead of a random one."""
    ends = list(ends)
    if not ends:
        raise InputError("fit_anchors: give at least one spring")
    bounds = (float(stiffness[0]), float(stiffness[1]))
    if not (0 <= bounds[0] < bounds[1]):
        raise InputError(f"fit_anchors: stiffness bounds must satisfy 0 ≤ lower < upper, got {stiffness!r}")
    if isinstance(draws, bool) or not isinstance(draws, int) or draws < 1:
        raise InputError(f"fit_anchors: draws must be an integer ≥ 1, got {draws!r}")
    box = (
        np.array([[*end.box_a[0], *end.box_b[0]] for end in ends], dtype=float),
        np.array([[*end.box_a[1], *end.box_b[1]] for end in ends], dtype=float),
    )
    if np.any(box[0] > box[1]):
        raise InputError("fit_anchors: a box has a lower corner above its upper corner")
    rng = np.random.default_rng(seed)
    best: AnchorFit | None = None
    for draw in range(draws):
        if draw == 0 and start is not None:  # a warm start: the first draw is the given design
            drawn, k_start = np.array([np.stack(pair) for pair in start.anchors]), start.stiffness
        else:
            drawn, k_start = rng.uniform(*box).reshape(len(ends), 2, 3), None
        anchors, k = _refine(system, ends, drawn, box, bounds, max_evaluations, k_start)
        relative = system.relative(ends, anchors, k)
        if best is None or relative < best.relative:
            best = AnchorFit(relative, [(za.copy(), zb.copy()) for za, zb in anchors], k, draw + 1)
        best.draws = draw + 1
        if best.relative <= target:
            break
    assert best is not None
    return best


def synthesize_in_boxes(
    mechanism: Mechanism,
    ends: Sequence[SpringEnds],
    stiffness: tuple[float, float] = (0.0, np.inf),
    draws: int = 4,
    seed: int = 0,
    names: Sequence[str] | None = None,
) -> tuple[AnchorFit, list[ZeroFreeLengthSpring]]:
    """Zero-free-length springs of a given topology with their anchors in their boxes, fitted to exact balance.

    ``ends`` names each spring's two bodies and the box [m] (lower, upper corner, link frame) its anchor
    may take on each; ``stiffness`` bounds every rate [N/m]. This is :func:`fit_anchors` on the arm's
    exact coefficients (:class:`CoefficientSystem`): ``fit.relative`` is the largest non-constant
    coefficient left over gravity's largest, so the design is exact when it is at most
    :data:`~springbalance.design.exact.multilinear.SPATIAL_EXACT`; a larger one is a design *not found*,
    not a proof (:func:`~springbalance.design.exact.spatial_reachability` proves). Returns the fit and the
    springs (named ``names``, default ``zfl1`` …)."""
    ends = list(ends)
    fit = fit_anchors(CoefficientSystem(mechanism), ends, stiffness=stiffness, draws=draws, seed=seed)
    return fit, fit.springs(ends, names)
