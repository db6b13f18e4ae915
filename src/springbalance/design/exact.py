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
given topology and stiffnesses, or why none exist). Spatial arms are left to the general
optimiser (:class:`~springbalance.design.problem.DesignProblem`); its result reports the residual
relative to the unbalanced torque and says "exactly balanced" when it is zero to solver
precision.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Sequence

import numpy as np
import pinocchio as pin

from springbalance.errors import InputError, SpringBalanceError
from springbalance.model.mechanism import GROUND, Mechanism
from springbalance.springs.params import Anchor, Free
from springbalance.springs.laws import ZeroFreeLengthSpring

#: a synthesis counts as exact when every block is below this fraction of the largest gravity block.
EXACT_TOLERANCE = 1e-12


class ExactBalanceUnreachable(SpringBalanceError):
    """No attachment points balance the chain exactly with the given spring topology.

    Attributes:
        synthesis: the :class:`ExactSynthesis` with the reason and the count check.
    """

    def __init__(self, message: str, synthesis=None):
        super().__init__(message)
        self.synthesis = synthesis


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
    bodies: tuple
    offsets: np.ndarray
    masses: np.ndarray
    mass_moments: np.ndarray
    gravity: complex
    _origin: np.ndarray          # world point of joint 1's axis (plane origin) [m]
    _basis: np.ndarray           # rows u, v, n: plane axes and the joint axis (world)
    _joint_points: np.ndarray    # complex O_j(0) (n), O_0 = 0
    _joint_of_frame: dict

    @property
    def size(self) -> int:
        """``n``: number of bodies, ground included."""
        return len(self.bodies)

    @classmethod
    def from_mechanism(cls, mechanism: Mechanism) -> "PlanarChain":
        """Read a planar serial chain from a mechanism.

        Needs revolute (or continuous) joints in series (each joint's parent is the previous
        one), all about parallel axes, and no mimic joints; otherwise raises
        :class:`~springbalance.errors.InputError` naming the culprit.
        """
        model = mechanism.model
        if model.njoints - 1 != mechanism.nv:
            raise InputError(f"mechanism {mechanism.name!r} has mimic joints; the planar exact-balance analysis "
                             "needs a serial chain of independent joints (use the optimiser)")
        for joint in mechanism.joints:
            if joint.kind == "prismatic":
                raise InputError(f"joint {joint.name!r} is prismatic; the planar exact-balance analysis needs revolute joints")
        for joint_id in range(1, model.njoints):
            if model.parents[joint_id] != joint_id - 1:
                raise InputError(f"joint {model.names[joint_id]!r} does not follow joint {model.names[joint_id - 1]!r}: "
                                 "the planar exact-balance analysis needs a serial chain")
        data = model.createData()
        q = mechanism.configurations(np.zeros((1, mechanism.nv)))[0]
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        axes = []
        for joint_id in range(1, model.njoints):
            jacobian = np.reshape(pin.getJointJacobian(model, data, joint_id, pin.LOCAL_WORLD_ALIGNED), (6, model.nv))
            axes.append(np.array(jacobian[3:, model.joints[joint_id].idx_v]))
        normal = axes[0] / np.linalg.norm(axes[0])
        for joint_id, axis in enumerate(axes, start=1):
            if np.linalg.norm(np.cross(axis, normal)) > 1e-9:
                raise InputError(f"joint {model.names[joint_id]!r} is not parallel to joint {model.names[1]!r}: "
                                 "the chain is not planar")
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        u = helper - (helper @ normal) * normal
        u /= np.linalg.norm(u)
        v = np.cross(normal, u)  # (u, v, n) right-handed: positive rotation about n turns u towards v
        basis = np.array([u, v, normal])
        origin = np.array(data.oMi[1].translation)

        def plane(point):
            relative = basis @ (np.asarray(point) - origin)
            return complex(relative[0], relative[1])

        n = model.njoints
        joint_points = np.array([0j] + [plane(data.oMi[j].translation) for j in range(1, n)])
        offsets = np.zeros(n, dtype=complex)
        offsets[1:n - 1] = joint_points[2:] - joint_points[1:n - 1]
        masses = np.zeros(n)
        moments = np.zeros(n, dtype=complex)
        for j in range(1, n):
            inertia = model.inertias[j]
            masses[j] = inertia.mass
            moments[j] = inertia.mass * (plane(data.oMi[j].act(inertia.lever)) - joint_points[j])
        gravity_world = np.asarray(mechanism.gravity)
        gravity = complex(gravity_world @ u, gravity_world @ v)
        bodies = [GROUND]
        joint_of_frame = {GROUND: 0}
        for frame_id, frame in enumerate(model.frames):
            if frame.type == pin.FrameType.BODY:
                joint_of_frame.setdefault(frame.name, int(frame.parentJoint))
        for j in range(1, n):
            names = [name for name, joint in joint_of_frame.items() if joint == j]
            bodies.append(names[0] if names else model.names[j])
        return cls(mechanism, tuple(bodies), offsets, masses, moments, gravity, origin, basis, joint_points,
                   joint_of_frame)

    # ---------------------------------------------------------------- bodies and points
    def body_index(self, body: str) -> int:
        """Index ``j`` of the chain body that carries link frame ``body`` (0 for the ground)."""
        self.mechanism.frame_id(body)  # raises on unknown names
        return self._joint_of_frame[body]

    def _frame(self, body: str):
        model = self.mechanism.model
        data = model.createData()
        pin.framesForwardKinematics(model, data, self.mechanism.configurations(np.zeros((1, self.mechanism.nv)))[0])
        return data.oMf[self.mechanism.frame_id(body)]

    def to_plane(self, body: str, point) -> complex:
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
        vector[max(a, 1):b] = self.offsets[max(a, 1):b]
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


@dataclasses.dataclass
class BalanceBlocks:
    """Off-diagonal blocks of the stiffness matrix of a design (how far from exact balance).

    Attributes:
        blocks: ``(body_i, body_j) -> K_ij`` (complex) [N·m], ``i < j``.
        gravity: the same blocks of the bare chain (no springs) [N·m].
    """

    blocks: dict
    gravity: dict

    @property
    def largest(self) -> float:
        """Largest ``|K_ij|`` [N·m]: 0 for exact balance."""
        return max((abs(value) for value in self.blocks.values()), default=0.0)

    @property
    def relative(self) -> float:
        """``largest`` over the largest gravity block."""
        scale = max((abs(value) for value in self.gravity.values()), default=0.0)
        return self.largest / scale if scale > 0 else float("nan")

    def matrices(self) -> dict:
        """The blocks as real 2×2 matrices ``[[α, -β], [β, α]]`` (``e_i^T M e_j``) [N·m]."""
        return {pair: np.array([[value.real, -value.imag], [value.imag, value.real]]) for pair, value in self.blocks.items()}

    @property
    def exact(self) -> bool:
        """Every block below 1e-9 of the largest gravity block: balanced at every pose."""
        return self.relative <= 1e-9


def _pair_blocks(chain: PlanarChain, matrix: np.ndarray) -> dict:
    return {(chain.bodies[i], chain.bodies[j]): complex(matrix[i, j])
            for i in range(chain.size) for j in range(i + 1, chain.size)}


def _chain_of(target) -> PlanarChain:
    return target if isinstance(target, PlanarChain) else PlanarChain.from_mechanism(target)


def residual_blocks(target, springs) -> BalanceBlocks:
    """Off-diagonal stiffness blocks [N·m] of a design with zero-free-length springs.

    ``target``: a :class:`PlanarChain` or a planar :class:`~springbalance.model.mechanism.Mechanism`;
    ``springs``: :class:`~springbalance.springs.laws.ZeroFreeLengthSpring` objects with fixed anchors
    and stiffness, or a :class:`~springbalance.results.result.DesignResult` (its springs at the design's values).
    """
    if hasattr(springs, "fixed_springs"):
        if target is None:
            target = springs.problem.mechanism
        springs = springs.fixed_springs()
    chain = _chain_of(target)
    entries = []
    for spring in springs:
        if not isinstance(spring, ZeroFreeLengthSpring):
            raise InputError(f"spring {spring.name!r} is {spring.kind}; the stiffness-matrix analysis needs "
                             "zero-free-length springs")
        if getattr(spring, "routed", False):
            raise InputError(f"spring {spring.name!r} is routed over pulleys; the stiffness-matrix analysis takes "
                             "straight zero-free-length springs (the residual of the design says whether it is exact)")
        anchors = spring.anchors
        if any(anchor.is_free for anchor in anchors.values()) or isinstance(spring.parameters["stiffness"], Free):
            raise InputError(f"spring {spring.name!r} has free anchors or stiffness; fix them (e.g. result.fixed_springs())")
        ends = [(chain.body_index(anchor.body), chain.to_plane(anchor.body, anchor.region().point([])))
                for anchor in (anchors["a"], anchors["b"])]
        if ends[0][0] == ends[1][0]:
            continue  # both ends on one body: a constant length
        (a, z_a), (b, z_b) = sorted(ends, key=lambda end: end[0])
        entries.append((a, b, z_a, z_b, float(spring.parameters["stiffness"])))
    gravity = _pair_blocks(chain, chain.blocks([]))
    return BalanceBlocks(_pair_blocks(chain, chain.blocks(entries)), gravity)


# ---------------------------------------------------------------------- count check
@dataclasses.dataclass(frozen=True)
class CountCheck:
    """Parameters against conditions: ``n(n-1)`` scalar conditions, 4 anchor coordinates per spring."""

    bodies: int
    springs: int
    conditions: int
    parameters: int
    minimum_springs: int

    @property
    def enough(self) -> bool:
        return self.parameters >= self.conditions

    def describe(self) -> str:
        verdict = "enough" if self.enough else "too few"
        return (f"{self.bodies} bodies (ground included): {self.conditions} scalar conditions; {self.springs} springs "
                f"give {self.parameters} anchor coordinates ({verdict}; at least {self.minimum_springs} springs needed)")


def count_check(target, springs: int | Sequence) -> CountCheck:
    """Count check for a chain (or its number of bodies ``n``) and a number (or list) of springs."""
    bodies = target if isinstance(target, int) else _chain_of(target).size
    count = springs if isinstance(springs, int) else len(springs)
    conditions = bodies * (bodies - 1)
    return CountCheck(bodies, count, conditions, 4 * count, math.ceil(conditions / 4))


# ---------------------------------------------------------------------- synthesis
@dataclasses.dataclass
class ExactSynthesis:
    """Outcome of :func:`synthesize`.

    Attributes:
        reachable: True when anchors were found that balance exactly.
        definitive: True when ``reachable`` is proven (found, or excluded by the structure).
        reason: why not, in words (empty when reachable).
        count: the :class:`CountCheck`.
        springs: fixed :class:`~springbalance.springs.laws.ZeroFreeLengthSpring` objects (when reachable).
        blocks: the :class:`BalanceBlocks` of those springs (when reachable).
    """

    reachable: bool
    definitive: bool
    reason: str
    count: CountCheck
    springs: list
    blocks: BalanceBlocks | None = None

    def require(self) -> list:
        """The springs, or :class:`ExactBalanceUnreachable` when exact balance is not reachable."""
        if not self.reachable:
            raise ExactBalanceUnreachable(f"exact balance is not reachable: {self.reason}", self)
        return self.springs


def _topology(chain: PlanarChain, topology) -> list[tuple]:
    entries = []
    for index, entry in enumerate(topology):
        try:
            body_a, body_b, stiffness = entry
        except (TypeError, ValueError):
            raise InputError(f"topology entry #{index + 1} must be (body_a, body_b, stiffness), got {entry!r}") from None
        a, b = chain.body_index(body_a), chain.body_index(body_b)
        if a == b:
            raise InputError(f"topology entry #{index + 1}: both ends on body {chain.bodies[a]!r}")
        stiffness = float(stiffness)
        if not np.isfinite(stiffness) or stiffness <= 0:
            raise InputError(f"topology entry #{index + 1}: stiffness must be > 0 [N/m], got {stiffness}")
        if a > b:  # order the ends ground-side first
            body_a, body_b, a, b = body_b, body_a, b, a
        entries.append((body_a, body_b, a, b, stiffness))
    if not entries:
        raise InputError("the topology has no springs")
    return entries


def synthesize(target, topology: Sequence[tuple], starts: int = 16, seed: int = 0,
               max_iterations: int = 200) -> ExactSynthesis:
    r"""Anchors that balance a planar chain exactly, for given spring pairs and stiffnesses.

    ``topology``: ``[(body_a, body_b, stiffness [N/m]), ...]`` with body names (link frames or
    ``"universe"``). First the structure: a gravity block :math:`K_{0j} \ne 0` with no spring
    from the ground to body ``j`` or beyond can never vanish (definitive "unreachable").
    Otherwise the bilinear conditions :math:`K_{ij} = 0` are solved for the 4 plane
    coordinates of each spring's anchors by a minimum-norm Gauss–Newton iteration from
    ``starts`` random starts; the solution with the smallest anchors is kept. Anchors lie in
    the plane of each body frame's origin.
    """
    chain = _chain_of(target)
    entries = _topology(chain, topology)
    count = count_check(chain, len(entries))
    gravity = chain.gravity_blocks()
    scale = float(np.max(np.abs(gravity)))  # [N·m]
    if scale == 0:
        raise InputError("gravity does not load this chain in its plane: nothing to balance")
    for j in range(1, chain.size):
        if abs(gravity[j]) > 1e-12 * scale and not any(a == 0 and b >= j for _, _, a, b, _ in entries):
            reason = (f"the ground–{chain.bodies[j]} block is the weight moment {abs(gravity[j]):.6g} N·m of "
                      f"{chain.bodies[j]} and beyond, and no spring joins the ground to {chain.bodies[j]} or a later "
                      f"body, so it cannot vanish (at least one spring must run from the ground to the last link; "
                      f"springs between consecutive bodies alone never balance a chain of two or more links exactly)")
            return ExactSynthesis(False, True, reason, count, [])

    pairs = [(i, j) for i in range(chain.size) for j in range(i + 1, chain.size)]
    rows = np.array([i for i, _ in pairs]), np.array([j for _, j in pairs])

    def residual(coordinates):
        z = coordinates[0::2] + 1j * coordinates[1::2]
        springs = [(a, b, z[2 * s], z[2 * s + 1], k) for s, (_, _, a, b, k) in enumerate(entries)]
        values = chain.blocks(springs)[rows] / scale
        return np.concatenate([values.real, values.imag])

    length = float(np.sum(np.abs(chain.offsets)) + np.max(np.abs(chain.mass_moments) / np.maximum(chain.masses, 1e-300)))
    rng = np.random.default_rng(seed)
    size = 4 * len(entries)
    step = 1e-3 * length  # central differences are exact for this quadratic residual
    solutions = []
    for _ in range(int(starts)):
        x = rng.uniform(-length, length, size)
        r = residual(x)
        for _ in range(max_iterations):
            if np.linalg.norm(r) < EXACT_TOLERANCE:
                break
            jacobian = np.empty((r.size, size))
            for column in range(size):
                offset = np.zeros(size)
                offset[column] = step
                jacobian[:, column] = (residual(x + offset) - residual(x - offset)) / (2 * step)
            delta = np.linalg.lstsq(jacobian, -r, rcond=None)[0]
            factor = 1.0
            while factor > 1e-6:
                trial = x + factor * delta
                trial_r = residual(trial)
                if np.linalg.norm(trial_r) < np.linalg.norm(r):
                    x, r = trial, trial_r
                    break
                factor /= 2
            else:
                break
        if np.linalg.norm(r) < EXACT_TOLERANCE:
            solutions.append((float(np.max(np.abs(x))), x))
    if not solutions:
        reason = (f"no anchors found from {starts} starts ({count.describe()})" if count.enough
                  else f"{count.describe()}; no anchors found from {starts} starts")
        return ExactSynthesis(False, False, reason, count, [])
    x = min(solutions, key=lambda item: item[0])[1]
    z = x[0::2] + 1j * x[1::2]
    springs = []
    for s, (body_a, body_b, a, b, stiffness) in enumerate(entries):
        springs.append(ZeroFreeLengthSpring(Anchor(body_a, chain.to_body(body_a, z[2 * s])),
                                            Anchor(body_b, chain.to_body(body_b, z[2 * s + 1])),
                                            name=f"zfl{s + 1}", stiffness=stiffness))
    return ExactSynthesis(True, True, "", count, springs, residual_blocks(chain, springs))
