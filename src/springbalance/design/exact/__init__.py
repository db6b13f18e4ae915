r"""Exact balance of planar serial chains with zero-free-length springs (stiffness-matrix method).

A planar serial chain of ``n`` bodies (body 0 the ground, bodies 1 … n−1 the links, every
joint revolute about parallel axes) is described in the plane by complex numbers. Body
``j`` turns by the absolute angle :math:`\varphi_j` (the sum of the joint angles up to
``j``, each counted positive about the first joint's axis); its unit direction is
:math:`w_j = e^{i\varphi_j}`, and :math:`w_0 = 1` for the ground. A point fixed in body ``j`` sits at

.. math:: x = \sum_{i=1}^{j-1} l_i\, w_i + z\, w_j \qquad [m],

with :math:`l_i` the vector from joint ``i`` to joint ``i+1`` and ``z`` the point relative to
joint ``j`` (both measured at the zero pose). Gravity (planar gravity vector :math:`\gamma`
[m/s²]) and every zero-free-length spring (:math:`V_s = k L^2/2`, docs/model.md §3.2) then make the
total potential a quadratic form in the direction vectors:

.. math::
    V = \text{const} + \sum_{0 \le i < j \le n-1} \operatorname{Re}\bigl(\bar w_i\, K_{ij}\, w_j\bigr),
    \qquad K_{ij} = -\bar\gamma\,\bigl(m_j c_j + l_j \textstyle\sum_{b>j} m_b\bigr)\,[i = 0]
                    + \sum_s k_s\, \bar D_{s,i}\, D_{s,j}\quad [J = N·m],

where spring ``s`` between bodies ``a < b`` has :math:`x_b - x_a = \sum_j D_{s,j} w_j`
(:math:`D_{s,j} = l_j` for :math:`\max(a,1) \le j < b`, then :math:`D_{s,a} \mathrel{-}= z_a`,
:math:`D_{s,b} \mathrel{+}= z_b`). A complex block :math:`K = \alpha + i\beta` is the 2×2 block
:math:`\begin{pmatrix}\alpha & -\beta\\ \beta & \alpha\end{pmatrix}` of the stiffness matrix
(:math:`e_i^T K e_j`); diagonal blocks give constants because :math:`|w_j| = 1`.

**Perfect balance ⇔ every off-diagonal block vanishes**: :math:`n(n-1)/2` complex, that is
:math:`n(n-1)` scalar conditions, for 4 anchor coordinates per spring, so at least
:math:`\lceil n(n-1)/4 \rceil` springs. A block :math:`K_{0j}` whose gravity part is not zero
can only be cancelled by a spring from the ground to body ``j`` or beyond; in particular the
last link needs a spring from the ground. Springs between consecutive bodies only therefore
never balance a two-link chain exactly (the ground–distal block is the distal link's weight
moment).

Use :meth:`PlanarChain.from_mechanism`, :func:`residual_blocks` (how far a design is from
exact, N·m), :func:`count_check` and :func:`synthesize` (anchors that balance exactly for a
given topology and stiffnesses, or why none exist).

**Spatial chains and trees** (any revolute axes; docs/model.md §9.1): the potential is multilinear in
``(1, cos θ_j, sin θ_j)``; :func:`spatial_coefficients` is the exact test (its coefficients from
Pinocchio on the grid ``{0, 2π/3, 4π/3}^n``), :func:`fit_stiffnesses` the stiffnesses of fixed anchors
(linear, NNLS), :func:`synthesize_spatial` builds an exactly balanced design pair by pair and
:func:`spatial_reachability` proves that a topology cannot balance.

The modules: :mod:`~springbalance.design.exact.chain` (:class:`PlanarChain`), :mod:`~springbalance.design.exact.blocks`
(:func:`residual_blocks`, :func:`count_check`), :mod:`~springbalance.design.exact.synthesis` (:func:`synthesize`),
:mod:`~springbalance.design.exact.multilinear` (:func:`spatial_coefficients`),
:mod:`~springbalance.design.exact.stiffness_fit` (:func:`fit_stiffnesses`),
:mod:`~springbalance.design.exact.anchor_fit` (:func:`synthesize_in_boxes`: a given topology's anchors in their boxes and
stiffnesses fitted to exact balance, the screen of ``explore``'s fewest-springs search),
:mod:`~springbalance.design.exact.spatial_tree` (pair matrices), :mod:`~springbalance.design.exact.spatial_blocks`
(one pair at a time) and :mod:`~springbalance.design.exact.spatial_synthesis` (:func:`synthesize_spatial`,
:func:`spatial_reachability`).
This package re-exports their public names.
"""

from __future__ import annotations

from springbalance.design.exact.anchor_fit import AnchorFit, SpringEnds, synthesize_in_boxes
from springbalance.design.exact.blocks import BalanceBlocks, CountCheck, count_check, residual_blocks
from springbalance.design.exact.chain import PlanarChain
from springbalance.design.exact.multilinear import SPATIAL_EXACT, SpatialCoefficients, spatial_coefficients
from springbalance.design.exact.spatial_synthesis import (
    SpatialReachability,
    SpatialSynthesis,
    SpatialVerdict,
    spatial_reachability,
    synthesize_spatial,
)
from springbalance.design.exact.stiffness_fit import StiffnessFit, fit_stiffnesses
from springbalance.design.exact.synthesis import EXACT_TOLERANCE, ExactBalanceUnreachable, ExactSynthesis, synthesize

__all__ = [
    "AnchorFit",
    "SpringEnds",
    "synthesize_in_boxes",
    "EXACT_TOLERANCE",
    "BalanceBlocks",
    "CountCheck",
    "ExactBalanceUnreachable",
    "ExactSynthesis",
    "PlanarChain",
    "SPATIAL_EXACT",
    "SpatialCoefficients",
    "SpatialReachability",
    "SpatialSynthesis",
    "SpatialVerdict",
    "StiffnessFit",
    "count_check",
    "fit_stiffnesses",
    "residual_blocks",
    "spatial_coefficients",
    "spatial_reachability",
    "synthesize",
    "synthesize_spatial",
]
