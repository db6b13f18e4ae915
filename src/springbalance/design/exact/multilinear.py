r"""The exact test of spatial balance: the multilinear coefficients of the potential (docs/model.md §9.1).

For a chain or tree of revolute (or continuous) joints whose springs are zero-free-length
(:math:`V_s = k L^2/2`), the total potential of gravity and springs is, up to a constant, a sum of
terms :math:`\operatorname{tr}(C_{pq}^T R_p^T R_q)` over pairs of bodies (docs/model.md §9.1). Each
relative rotation is a product of joint rotations
:math:`\mathrm{Rot}(a, \theta) = I + \sin\theta\,[a]_\times + (1 - \cos\theta)[a]_\times^2`, so

.. math:: V(\theta) = \sum_{\alpha \in \{0,1,2\}^n} c_\alpha \prod_{j=1}^{n} \phi_{\alpha_j}(\theta_j),
    \qquad \phi_0 = 1,\ \phi_1 = \cos,\ \phi_2 = \sin \qquad [J]

is *multilinear* in :math:`(1, \cos\theta_j, \sin\theta_j)` per joint. The :math:`3^n` products are
linearly independent functions, so **the arm is balanced exactly at every pose ⇔ every
coefficient** :math:`c_\alpha` **with** :math:`\alpha \ne 0` **vanishes**. The coefficients are
found exactly from :math:`V` on the grid :math:`\{0, 2\pi/3, 4\pi/3\}^n`: along each axis the
3×3 map :math:`F_{ta} = \phi_a(2\pi t/3)` is inverted
(:math:`F^{-1} = \tfrac13 [1, 1, 1;\ 2\cos\vartheta_t;\ 2\sin\vartheta_t]`), which is exact for any
function of that form (a discrete Fourier transform of degree one).

``V`` is evaluated with Pinocchio (:func:`~springbalance.model.kinematics.gravity_and_potential` for
gravity, body placements for the springs); :func:`spatial_coefficients` returns
:class:`SpatialCoefficients`, the coefficients of the design against those of gravity alone.
"""

from __future__ import annotations

import dataclasses
import itertools
from typing import Iterable, Sequence

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.exact.blocks import _FixedDesign
from springbalance.design.exact.chain import require_independent_revolute
from springbalance.design.problem import DesignProblem
from springbalance.errors import InputError
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws import Spring, ZeroFreeLengthSpring
from springbalance.springs.params import Free

#: a design balances exactly when its largest non-constant coefficient is below this fraction of gravity's
SPATIAL_EXACT = 1e-9
#: the grid of every joint [rad]
GRID = 2 * np.pi * np.arange(3) / 3
#: the inverse of ``F_ta = φ_a(GRID[t])``: rows ``a`` = 1, cos, sin; columns the grid points
INVERSE = np.array([np.full(3, 1 / 3), 2 * np.cos(GRID) / 3, 2 * np.sin(GRID) / 3])
_BASIS = ("1", "cos", "sin")


@dataclasses.dataclass
class _Samples:
    """The grid poses of a mechanism (what :class:`WorkspaceKinematics` reads)."""

    mechanism: Mechanism
    configurations: np.ndarray


@dataclasses.dataclass
class SpatialCoefficients:
    r"""The multilinear coefficients of a design's potential (see the module documentation).

    Attributes:
        joints: the joint names (axis ``j`` of the arrays).
        coefficients: :math:`c_\alpha` (shape ``(3,)*n``; index 0, 1, 2 = 1, cos, sin) of gravity and springs [J].
        gravity: the same of gravity alone (the bare arm) [J].
    """

    joints: list[str]
    coefficients: np.ndarray
    gravity: np.ndarray

    @staticmethod
    def _largest(array: np.ndarray) -> float:
        flat = np.abs(array).ravel().copy()
        flat[0] = 0.0  # the constant
        return float(flat.max()) if flat.size else 0.0

    @property
    def largest(self) -> float:
        """Largest ``|c_α|``, ``α ≠ 0`` [J]: 0 for exact balance."""
        return self._largest(self.coefficients)

    @property
    def gravity_scale(self) -> float:
        """Largest non-constant coefficient of gravity alone [J]."""
        return self._largest(self.gravity)

    @property
    def relative(self) -> float:
        """``largest`` over ``gravity_scale`` (nan when gravity does not load the arm)."""
        scale = self.gravity_scale
        return self.largest / scale if scale > 0 else float("nan")

    @property
    def exact(self) -> bool:
        """Every non-constant coefficient below :data:`SPATIAL_EXACT` of gravity's largest."""
        return self.relative <= SPATIAL_EXACT

    def terms(self, tolerance: float = SPATIAL_EXACT) -> dict[str, float]:
        """The non-constant coefficients above ``tolerance`` × gravity's largest, by name
        (``"cos elbow · sin wrist"``) [J], largest first."""
        limit = tolerance * self.gravity_scale
        named = {}
        for index in zip(*np.nonzero(np.abs(self.coefficients) > limit)):
            if any(index):
                name = " · ".join(f"{_BASIS[a]} {joint}" for a, joint in zip(index, self.joints) if a)
                named[name] = float(self.coefficients[index])
        return dict(sorted(named.items(), key=lambda item: -abs(item[1])))

    def value(self, angles: Sequence[float]) -> float:
        """``V`` [J] at joint angles ``angles`` [rad] from the coefficients."""
        result = self.coefficients
        for angle in angles:
            result = np.tensordot(np.array([1.0, np.cos(angle), np.sin(angle)]), result, axes=(0, 0))
        return float(result)


def check_revolute(mechanism: Mechanism) -> None:
    """InputError naming the culprit unless every joint is an independent revolute or continuous joint."""
    require_independent_revolute(
        mechanism,
        "spatial exact test",
        "independent revolute joints (its potential is then multilinear in cos and sin of each)",
        " (a spring's potential is quadratic in a slider's travel)",
    )
    if mechanism.nv > 10:
        raise InputError(f"mechanism {mechanism.name!r} has {mechanism.nv} joints: 3^{mechanism.nv} poses is too many")


def grid_kinematics(mechanism: Mechanism) -> WorkspaceKinematics:
    """Pinocchio's kinematics on the grid ``{0, 2π/3, 4π/3}^n`` (C order: the last joint fastest)."""
    check_revolute(mechanism)
    angles = np.array(list(itertools.product(GRID, repeat=mechanism.nv))).reshape(-1, mechanism.nv)
    return WorkspaceKinematics(_Samples(mechanism, mechanism.configurations(angles)))


def coefficients_of(values: np.ndarray, joints: int) -> np.ndarray:
    """The multilinear coefficients (shape ``(3,)*joints``) of values on the grid (``3^joints``, C order)."""
    tensor = np.asarray(values, dtype=float).reshape((3,) * joints)
    for axis in range(joints):
        tensor = np.moveaxis(np.tensordot(INVERSE, tensor, axes=(1, axis)), 0, axis)
    return tensor


def fixed_zfl(spring: Spring) -> tuple[ZeroFreeLengthSpring, float, float]:
    """The spring with its stiffness [N/m] and own mass [kg]; InputError unless it is a straight
    zero-free-length spring with fixed anchors and stiffness."""
    if not isinstance(spring, ZeroFreeLengthSpring):
        raise InputError(
            f"spring {spring.name!r} is {spring.kind}; the spatial exact test needs zero-free-length springs "
            "(only their potential is multilinear in the joints' cos and sin)"
        )
    if spring.routed:
        raise InputError(
            f"spring {spring.name!r} is routed over pulleys; the spatial exact test takes straight springs"
        )
    stiffness = spring.parameters["stiffness"]
    if isinstance(stiffness, Free) or any(anchor.is_free for anchor in spring.anchors.values()):
        raise InputError(
            f"spring {spring.name!r} has free anchors or stiffness; fix them (e.g. result.fixed_springs())"
        )
    mass = spring.spring_mass({"stiffness": float(stiffness)})
    return spring, float(stiffness), float(mass)


def spring_grid_potential(
    kinematics: WorkspaceKinematics, spring: ZeroFreeLengthSpring, stiffness: float, mass: float = 0.0
) -> np.ndarray:
    """``k |x_b − x_a|² / 2 − (m_s/2) g·(x_a + x_b)`` [J] of one spring at the grid poses."""
    ends = [
        kinematics.body(anchor.body).points(anchor.region().point([]))
        for anchor in (spring.anchors["a"], spring.anchors["b"])
    ]
    gravity = kinematics.mechanism.gravity
    elastic = 0.5 * stiffness * np.sum((ends[1] - ends[0]) ** 2, axis=1)
    return elastic - 0.5 * mass * (ends[0] + ends[1]) @ gravity


def spatial_coefficients(
    target: Mechanism | _FixedDesign | DesignProblem,
    springs: Iterable[Spring] | np.ndarray | None = None,
) -> SpatialCoefficients:
    """The multilinear coefficients of a design's potential (module documentation).

    ``target``: a :class:`~springbalance.model.mechanism.Mechanism` with ``springs`` (fixed
    :class:`~springbalance.springs.laws.ZeroFreeLengthSpring` objects), a design result (its springs at the
    design's values), or a :class:`~springbalance.design.problem.DesignProblem` with its design vector
    ``x`` as ``springs``.
    """
    if isinstance(target, _FixedDesign):
        mechanism, fixed = target.problem.mechanism, list(target.fixed_springs())
    elif isinstance(target, Mechanism):
        mechanism, fixed = target, list(springs if springs is not None else [])
    elif isinstance(target, DesignProblem) and springs is not None:
        design = EvaluatedDesign(target, np.asarray(springs, dtype=float))
        mechanism, fixed = design.problem.mechanism, list(design.fixed_springs())
    else:
        raise InputError(
            "spatial_coefficients: give a mechanism and its fixed springs, a design result, or a problem and x"
        )
    kinematics = grid_kinematics(mechanism)
    gravity = np.asarray(kinematics.potential, dtype=float)
    total = gravity.copy()
    for spring in fixed:
        zfl, stiffness, mass = fixed_zfl(spring)
        total += spring_grid_potential(kinematics, zfl, stiffness, mass)
    joints = mechanism.nv
    return SpatialCoefficients(mechanism.joint_names, coefficients_of(total, joints), coefficients_of(gravity, joints))
