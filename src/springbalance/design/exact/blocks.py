"""How far a design is from exact balance (:func:`residual_blocks`), and the count of conditions against
anchor coordinates (:func:`count_check`)."""

from __future__ import annotations

import dataclasses
import math
from typing import Iterable, Protocol, Sequence, runtime_checkable

import numpy as np

from springbalance.design.exact.chain import PlanarChain, as_chain
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism
from springbalance.springs.laws import Spring, ZeroFreeLengthSpring
from springbalance.springs.params import Free


@dataclasses.dataclass
class BalanceBlocks:
    """Off-diagonal blocks of the stiffness matrix of a design (how far from exact balance).

    Attributes:
        blocks: ``(body_i, body_j) -> K_ij`` (complex) [N·m], ``i < j``.
        gravity: the same blocks of the bare chain (no springs) [N·m].
    """

    blocks: dict[tuple[str, str], complex]
    gravity: dict[tuple[str, str], complex]

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
        return {
            pair: np.array([[value.real, -value.imag], [value.imag, value.real]]) for pair, value in self.blocks.items()
        }

    @property
    def exact(self) -> bool:
        """Every block below 1e-9 of the largest gravity block: balanced at every pose."""
        return self.relative <= 1e-9


class _OnMechanism(Protocol):
    @property
    def mechanism(self) -> Mechanism:
        """The arm."""


@runtime_checkable
class _FixedDesign(Protocol):
    """A design on its problem (a :class:`~springbalance.design.evaluated.EvaluatedDesign`): its springs at
    the design's values and its problem's mechanism."""

    @property
    def problem(self) -> _OnMechanism:
        """The design problem."""

    def fixed_springs(self) -> list[Spring]:
        """The springs with every free parameter and anchor fixed at the design's values."""


def _pair_blocks(chain: PlanarChain, matrix: np.ndarray) -> dict[tuple[str, str], complex]:
    return {
        (chain.bodies[i], chain.bodies[j]): complex(matrix[i, j])
        for i in range(chain.size)
        for j in range(i + 1, chain.size)
    }


def residual_blocks(target: PlanarChain | Mechanism | None, springs: Iterable[Spring] | _FixedDesign) -> BalanceBlocks:
    """Off-diagonal stiffness blocks [N·m] of a design with zero-free-length springs.

    ``target``: a :class:`PlanarChain` or a planar :class:`~springbalance.model.mechanism.Mechanism`;
    ``springs``: :class:`~springbalance.springs.laws.ZeroFreeLengthSpring` objects with fixed anchors
    and stiffness, or a :class:`~springbalance.results.result.DesignResult` (its springs at the design's values).
    """
    if isinstance(springs, _FixedDesign):
        if target is None:
            target = springs.problem.mechanism
        springs = springs.fixed_springs()
    if target is None:
        raise InputError("residual_blocks: give the chain or mechanism (target) with a list of springs")
    chain = as_chain(target)
    entries = []
    for spring in springs:
        if not isinstance(spring, ZeroFreeLengthSpring):
            raise InputError(
                f"spring {spring.name!r} is {spring.kind}; the stiffness-matrix analysis needs zero-free-length springs"
            )
        if getattr(spring, "routed", False):
            raise InputError(
                f"spring {spring.name!r} is routed over pulleys; the stiffness-matrix analysis takes "
                "straight zero-free-length springs (the residual of the design says whether it is exact)"
            )
        anchors = spring.anchors
        if any(anchor.is_free for anchor in anchors.values()) or isinstance(spring.parameters["stiffness"], Free):
            raise InputError(
                f"spring {spring.name!r} has free anchors or stiffness; fix them (e.g. result.fixed_springs())"
            )
        ends = [
            (chain.body_index(anchor.body), chain.to_plane(anchor.body, anchor.region().point([])))
            for anchor in (anchors["a"], anchors["b"])
        ]
        if ends[0][0] == ends[1][0]:
            continue  # both ends on one body: a constant length
        (a, z_a), (b, z_b) = sorted(ends, key=lambda end: end[0])
        entries.append((a, b, z_a, z_b, float(spring.parameters["stiffness"])))
    gravity = _pair_blocks(chain, chain.blocks([]))
    return BalanceBlocks(_pair_blocks(chain, chain.blocks(entries)), gravity)


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
        return (
            f"{self.bodies} bodies (ground included): {self.conditions} scalar conditions; {self.springs} springs "
            f"give {self.parameters} anchor coordinates ({verdict}; at least {self.minimum_springs} springs needed)"
        )


def count_check(target: int | PlanarChain | Mechanism, springs: int | Sequence) -> CountCheck:
    """Count check for a chain (or its number of bodies ``n``) and a number (or list) of springs."""
    bodies = target if isinstance(target, int) else as_chain(target).size
    count = springs if isinstance(springs, int) else len(springs)
    conditions = bodies * (bodies - 1)
    return CountCheck(bodies, count, conditions, 4 * count, math.ceil(conditions / 4))
