r"""Stiffnesses for fixed anchors: the exact-balance conditions are linear in ``k`` (docs/model.md §9.1).

With every anchor fixed, spring ``s`` adds :math:`k_s\,a_s` to the multilinear coefficients of the
potential (:mod:`~springbalance.design.exact.multilinear`), :math:`a_s` those of
:math:`\tfrac12 |x_b - x_a|^2` [m²]. Exact balance is then the linear system
:math:`A k = -c_g` on the non-constant coefficients, with :math:`k \ge 0` [N/m] and :math:`c_g` those of
gravity (and of the springs' own fixed masses) [J]. :func:`fit_stiffnesses` solves it by non-negative least
squares (``scipy.optimize.nnls``): the smallest :math:`\lVert A k + c_g \rVert_2` over :math:`k \ge 0`;
a zero residual proves the anchors can balance exactly, a positive one that they cannot (whatever the
stiffnesses). Given many candidate anchors at once, the fit picks the springs it needs (the rest get
:math:`k = 0`): a screen of candidate anchors.
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np

from springbalance.design.exact.multilinear import (
    SPATIAL_EXACT,
    SpatialCoefficients,
    coefficients_of,
    grid_kinematics,
    spring_grid_potential,
)
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws import ZeroFreeLengthSpring
from springbalance.springs.mass import CoilMass
from springbalance.springs.params import Anchor


@dataclasses.dataclass
class StiffnessFit:
    """Outcome of :func:`fit_stiffnesses`.

    Attributes:
        stiffness: ``k`` per candidate [N/m] (0 for a candidate the fit does not use).
        springs: the candidates with ``k > 0``, as fixed zero-free-length springs.
        coefficients: the :class:`~springbalance.design.exact.multilinear.SpatialCoefficients` of those springs.
        residual: :math:`\\lVert A k + c_g \\rVert_2` [J].
    """

    stiffness: np.ndarray
    springs: list[ZeroFreeLengthSpring]
    coefficients: SpatialCoefficients
    residual: float

    @property
    def relative(self) -> float:
        """The largest non-constant coefficient left, relative to gravity's largest."""
        return self.coefficients.relative

    @property
    def exact(self) -> bool:
        """Exact balance reached (to :data:`~springbalance.design.exact.multilinear.SPATIAL_EXACT`)."""
        return self.coefficients.relative <= SPATIAL_EXACT

    def describe(self) -> str:
        used = int(np.count_nonzero(self.stiffness))
        verdict = "exact balance" if self.exact else f"residual {self.relative:.3g} of gravity's largest coefficient"
        return f"{used} of {self.stiffness.size} candidate springs used: {verdict}"


def _candidate(spring: ZeroFreeLengthSpring, index: int) -> tuple[Anchor, Anchor, float]:
    """The two fixed anchors of a candidate and its own fixed mass [kg]."""
    if not isinstance(spring, ZeroFreeLengthSpring) or spring.routed:
        raise InputError(f"candidate #{index + 1} must be a straight zero-free-length spring, got {spring!r}")
    if any(anchor.is_free for anchor in spring.anchors.values()):
        raise InputError(f"candidate #{index + 1} ({spring.name!r}) has a free anchor; the fit needs fixed anchors")
    if isinstance(spring.mass, CoilMass):
        raise InputError(
            f"candidate #{index + 1} ({spring.name!r}) has a mass coupled to its stiffness: the balance is then "
            "not linear in k"
        )
    return spring.anchors["a"], spring.anchors["b"], float(spring.spring_mass({"stiffness": 0.0}))


def fit_stiffnesses(mechanism: Mechanism, candidates: Sequence[ZeroFreeLengthSpring]) -> StiffnessFit:
    """The stiffnesses ``k ≥ 0`` [N/m] of candidate springs (fixed anchors; their stiffness is ignored, fixed or
    free) that come closest to exact balance (module documentation)."""
    from scipy.optimize import nnls  # scipy.optimize stays out of start-up (tests/test_package.py)

    candidates = list(candidates)
    if not candidates:
        raise InputError("fit_stiffnesses: give at least one candidate spring")
    ends = [_candidate(spring, index) for index, spring in enumerate(candidates)]
    kinematics = grid_kinematics(mechanism)
    joints = mechanism.nv
    target = np.asarray(kinematics.potential, dtype=float).copy()
    columns = []
    for (a, b, mass), spring in zip(ends, candidates):
        unit = ZeroFreeLengthSpring(a, b, name=spring.name, stiffness=1.0)
        target += spring_grid_potential(kinematics, unit, 0.0, mass)
        columns.append(coefficients_of(spring_grid_potential(kinematics, unit, 1.0), joints).ravel()[1:])
    matrix = np.array(columns).T  # [m²] per [N/m]: coefficients [J]
    gravity = coefficients_of(target, joints).ravel()[1:]
    scale = np.maximum(np.max(np.abs(matrix), axis=0), 1e-300)  # column scaling for the solver
    scaled, _ = nnls(matrix / scale, -gravity, maxiter=50 * matrix.shape[1])
    stiffness = scaled / scale
    stiffness[stiffness < 1e-12 * max(float(stiffness.max()), 0.0)] = 0.0  # round-off of the solver
    residual = float(np.linalg.norm(matrix @ stiffness + gravity))
    springs = [
        ZeroFreeLengthSpring(a, b, name=spring.name or f"zfl{index + 1}", stiffness=float(k), mass=mass or None)
        for index, ((a, b, mass), spring, k) in enumerate(zip(ends, candidates, stiffness))
        if k > 0
    ]
    used = [float(k) for k in stiffness if k > 0]
    total = target + sum((spring_grid_potential(kinematics, s, k) for s, k in zip(springs, used)), 0.0)
    gravity_alone = coefficients_of(kinematics.potential, joints)
    coefficients = SpatialCoefficients(mechanism.joint_names, coefficients_of(total, joints), gravity_alone)
    return StiffnessFit(stiffness, springs, coefficients, residual)
