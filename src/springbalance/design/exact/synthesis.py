"""Anchors that balance a planar chain exactly for a given spring topology (:func:`synthesize`)."""

from __future__ import annotations

import dataclasses
from typing import Callable, Sequence

import numpy as np

from springbalance.design.exact.blocks import BalanceBlocks, CountCheck, count_check, residual_blocks
from springbalance.design.exact.chain import PlanarChain, as_chain
from springbalance.errors import InputError, SpringBalanceError
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws import ZeroFreeLengthSpring
from springbalance.springs.params import Anchor

#: a synthesis counts as exact when every block is below this fraction of the largest gravity block.
EXACT_TOLERANCE = 1e-12


class ExactBalanceUnreachable(SpringBalanceError):
    """No attachment points balance the chain exactly with the given spring topology.

    Attributes:
        synthesis: the :class:`ExactSynthesis` with the reason and the count check.
    """

    def __init__(self, message: str, synthesis: ExactSynthesis | None = None) -> None:
        super().__init__(message)
        self.synthesis = synthesis


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
    springs: list[ZeroFreeLengthSpring]
    blocks: BalanceBlocks | None = None

    def require(self) -> list[ZeroFreeLengthSpring]:
        """The springs, or :class:`ExactBalanceUnreachable` when exact balance is not reachable."""
        if not self.reachable:
            raise ExactBalanceUnreachable(f"exact balance is not reachable: {self.reason}", self)
        return self.springs


def _topology(chain: PlanarChain, topology: Sequence[tuple]) -> list[tuple]:
    entries = []
    for index, entry in enumerate(topology):
        try:
            body_a, body_b, stiffness = entry
        except (TypeError, ValueError):
            raise InputError(
                f"topology entry #{index + 1} must be (body_a, body_b, stiffness), got {entry!r}"
            ) from None
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


def synthesize(
    target: PlanarChain | Mechanism,
    topology: Sequence[tuple],
    starts: int = 16,
    seed: int = 0,
    max_iterations: int = 200,
) -> ExactSynthesis:
    r"""Anchors that balance a planar chain exactly, for given spring pairs and stiffnesses.

    ``topology``: ``[(body_a, body_b, stiffness [N/m]), ...]`` with body names (link frames or
    ``"universe"``). First the structure: a gravity block :math:`K_{0j} \ne 0` with no spring
    from the ground to body ``j`` or beyond can never vanish (definitive "unreachable").
    Otherwise the bilinear conditions :math:`K_{ij} = 0` are solved for the 4 plane
    coordinates of each spring's anchors by a minimum-norm Gauss–Newton iteration from
    ``starts`` random starts; the solution with the smallest anchors is kept. Anchors lie in
    the plane of each body frame's origin.
    """
    chain = as_chain(target)
    entries = _topology(chain, topology)
    count = count_check(chain, len(entries))
    gravity = chain.gravity_blocks()
    scale = float(np.max(np.abs(gravity)))  # [N·m]
    if scale == 0:
        raise InputError("gravity does not load this chain in its plane: nothing to balance")
    reason = _structural_obstruction(chain, entries, gravity, scale)
    if reason:
        return ExactSynthesis(False, True, reason, count, [])
    solutions = _anchor_solutions(chain, entries, scale, starts, seed, max_iterations)
    if not solutions:
        reason = (
            f"no anchors found from {starts} starts ({count.describe()})"
            if count.enough
            else f"{count.describe()}; no anchors found from {starts} starts"
        )
        return ExactSynthesis(False, False, reason, count, [])
    springs = _synthesized_springs(chain, entries, min(solutions, key=lambda item: item[0])[1])
    return ExactSynthesis(True, True, "", count, springs, residual_blocks(chain, springs))


def _structural_obstruction(chain: PlanarChain, entries: list[tuple], gravity: np.ndarray, scale: float) -> str:
    r"""Why no anchors can balance the chain with this topology (empty when the structure allows it): a gravity
    block :math:`K_{0j} \ne 0` [N·m] with no spring from the ground to body ``j`` or beyond."""
    for j in range(1, chain.size):
        if abs(gravity[j]) > 1e-12 * scale and not any(a == 0 and b >= j for _, _, a, b, _ in entries):
            return (
                f"the ground–{chain.bodies[j]} block is the weight moment {abs(gravity[j]):.6g} N·m of "
                f"{chain.bodies[j]} and beyond, and no spring joins the ground to {chain.bodies[j]} or a later "
                f"body, so it cannot vanish (at least one spring must run from the ground to the last link; "
                f"springs between consecutive bodies alone never balance a chain of two or more links exactly)"
            )
    return ""


def _anchor_solutions(
    chain: PlanarChain, entries: list[tuple], scale: float, starts: int, seed: int, max_iterations: int
) -> list[tuple[float, np.ndarray]]:
    """``(largest |coordinate| [m], coordinates)`` of every start whose Gauss–Newton iteration reached
    :math:`K_{ij} = 0` (to :data:`EXACT_TOLERANCE` of ``scale``); coordinates: ``(Re z, Im z)`` of each
    spring's two anchors in turn."""
    pairs = [(i, j) for i in range(chain.size) for j in range(i + 1, chain.size)]
    rows = np.array([i for i, _ in pairs]), np.array([j for _, j in pairs])

    def residual(coordinates: np.ndarray) -> np.ndarray:
        z = coordinates[0::2] + 1j * coordinates[1::2]
        springs = [(a, b, z[2 * s], z[2 * s + 1], k) for s, (_, _, a, b, k) in enumerate(entries)]
        values = chain.blocks(springs)[rows] / scale
        return np.concatenate([values.real, values.imag])

    length = float(
        np.sum(np.abs(chain.offsets)) + np.max(np.abs(chain.mass_moments) / np.maximum(chain.masses, 1e-300))
    )
    rng = np.random.default_rng(seed)
    size = 4 * len(entries)
    step = 1e-3 * length  # central differences are exact for this quadratic residual
    solutions = []
    for _ in range(int(starts)):
        x, r = _gauss_newton(residual, rng.uniform(-length, length, size), max_iterations, step)
        if np.linalg.norm(r) < EXACT_TOLERANCE:
            solutions.append((float(np.max(np.abs(x))), x))
    return solutions


def _gauss_newton(
    residual: Callable[[np.ndarray], np.ndarray], x: np.ndarray, max_iterations: int, step: float
) -> tuple[np.ndarray, np.ndarray]:
    """Minimum-norm Gauss–Newton steps (central-difference Jacobian, halved until the norm drops) from ``x``;
    returns ``(x, residual(x))`` where it stopped."""
    size = x.size
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
    return x, r


def _synthesized_springs(chain: PlanarChain, entries: list[tuple], x: np.ndarray) -> list[ZeroFreeLengthSpring]:
    """The fixed zero-free-length springs of the topology ``entries`` with the anchors ``x`` (plane coordinates)."""
    z = x[0::2] + 1j * x[1::2]
    springs = []
    for s, (body_a, body_b, _, _, stiffness) in enumerate(entries):
        springs.append(
            ZeroFreeLengthSpring(
                Anchor(body_a, chain.to_body(body_a, z[2 * s])),
                Anchor(body_b, chain.to_body(body_b, z[2 * s + 1])),
                name=f"zfl{s + 1}",
                stiffness=stiffness,
            )
        )
    return springs
