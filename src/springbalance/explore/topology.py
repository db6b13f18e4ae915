r"""Spring topologies of a study: which candidates carry a spring, enumerated and pruned.

A **topology** is a set of 1 … ``max_springs`` distinct candidates
(:mod:`springbalance.explore.candidates`). Before anything is solved, the enumeration is pruned:

- **Symmetry.** A topology is a *set*: the ``k!`` orderings of its springs are one design, and
  bodies welded to each other are one candidate (:class:`~springbalance.explore.candidates.BodyTree`).
- **Reachability** (planar serial chains with zero-free-length springs; docs/model.md §9). With
  body ``0`` the ground, exact balance needs every off-diagonal block
  :math:`K_{ij} = G_{ij} + \sum_s k_s \bar D_{s,i} D_{s,j}` of the stiffness matrix to vanish. A
  spring from body ``a`` to body ``b`` (``a < b``) has :math:`D_{s,j} \ne 0` exactly for
  ``j ∈ {a} ∪ [max(a, 1), b]``, so it reaches the blocks between those bodies. A topology is
  **proven unreachable** when

  1. it has fewer than :math:`\lceil n(n-1)/4 \rceil` springs (``n(n-1)`` real conditions, four
     anchor coordinates per spring), or
  2. a gravity block :math:`G_{0j} \ne 0` is reached by no spring (it can never be cancelled);

  and **unreachable but for degenerate anchors** when a block without gravity is reached by one
  spring only: its product :math:`k \bar D_i D_j` must vanish, which puts an anchor on a joint
  axis, where the spring is another topology's.
- **Spatial reachability** (chains and trees of revolute joints with any axes, zero-free-length
  springs; docs/model.md §9.1; :class:`~springbalance.design.exact.SpatialReachability`). A topology is
  proven unreachable when gravity has a non-zero multilinear coefficient on joints that no spring's
  path crosses, or when an outermost spring pair needs more springs than it has.
- **Size.** :func:`count_topologies` counts a study before enumerating it; a study of more than
  :data:`MAX_TOPOLOGIES` topologies is refused (``explore.max_topologies`` raises the limit).
- **Dominance** (while the study runs): a topology is not solved when one of its subsets already
  balances exactly (:class:`~springbalance.explore.study.Study` solves by spring count).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from typing import Sequence

import numpy as np

from springbalance.design.exact import PlanarChain, SpatialReachability, synthesize_spatial
from springbalance.errors import InputError
from springbalance.explore.candidates import Candidate
from springbalance.model.mechanism import Mechanism

#: a gravity block counts as zero below this fraction of the largest one
GRAVITY_ZERO = 1e-12
#: the most topologies a study enumerates unless ``explore.max_topologies`` says otherwise
MAX_TOPOLOGIES = 20000


@dataclasses.dataclass(frozen=True)
class Verdict:
    """Why a topology is not solved: ``kind`` is ``unreachable`` (proven), ``degenerate`` or ``dominated``."""

    kind: str
    reason: str


def _ordered(first: int, second: int) -> tuple[int, int]:
    """The two chain body indices, the lower first."""
    low, high = sorted((first, second))
    return low, high


class Reachability:
    """The exact-balance reachability test of a planar chain (see the module documentation)."""

    def __init__(self, mechanism: Mechanism, candidates: Sequence[Candidate]):
        self.chain = PlanarChain.from_mechanism(mechanism)
        gravity = np.abs(self.chain.gravity_blocks())
        self.loaded = [j for j in range(1, self.chain.size) if gravity[j] > GRAVITY_ZERO * max(gravity.max(), 1e-300)]
        self.ends = [_ordered(self.chain.body_index(c.a), self.chain.body_index(c.b)) for c in candidates]

    def reached(self, spring: tuple[int, int]) -> set[tuple[int, int]]:
        """The blocks ``(i, j)`` (``i < j``) of the stiffness matrix that a spring between chain bodies
        ``spring = (a, b)`` reaches."""
        a, b = spring
        bodies = sorted({a, *range(max(a, 1), b + 1)})
        return set(itertools.combinations(bodies, 2))

    def verdict(self, topology: Sequence[int]) -> Verdict | None:
        """None when exact balance may be reached; else why not."""
        n = self.chain.size
        needed = math.ceil(n * (n - 1) / 4)
        if len(topology) < needed:
            return Verdict(
                "unreachable",
                f"{len(topology)} spring(s) give {4 * len(topology)} anchor coordinates for "
                f"{n * (n - 1)} conditions: at least {needed} springs are needed",
            )
        reach = [self.reached(self.ends[index]) for index in topology]
        names = self.chain.bodies
        for j in self.loaded:
            if not any((0, j) in blocks for blocks in reach):
                return Verdict(
                    "unreachable",
                    f"the weight moment of {names[j]!r} and beyond (block K_0{j}) is reached "
                    f"by no spring from the ground to {names[j]!r} or further out",
                )
        counts: dict[tuple[int, int], int] = {}
        for blocks in reach:
            for block in blocks:
                counts[block] = counts.get(block, 0) + 1
        for (i, j), count in sorted(counts.items()):
            if count == 1 and not (i == 0 and j in self.loaded):
                return Verdict(
                    "degenerate",
                    f"block K_{i}{j} ({names[i]!r}, {names[j]!r}) is reached by one spring "
                    "only: it vanishes only with an anchor on a joint axis (another topology)",
                )
        return None


def count_topologies(count: int, max_springs: int) -> int:
    """How many sets of 1 … ``max_springs`` of ``count`` candidates there are (without enumerating them)."""
    return sum(math.comb(count, size) for size in range(1, min(max_springs, count) + 1))


def enumerate_topologies(count: int, max_springs: int, limit: int | None = None) -> list[tuple[int, ...]]:
    """Every set of 1 … ``max_springs`` of ``count`` candidates, fewer springs first; InputError when there are
    more than ``limit`` (None: no limit)."""
    if isinstance(max_springs, bool) or not isinstance(max_springs, int) or max_springs < 1:
        raise InputError(f"max_springs must be an integer ≥ 1, got {max_springs!r}")
    total = count_topologies(count, max_springs)
    if limit is not None and total > limit:
        raise InputError(
            f"{count} candidates with up to {max_springs} springs make {total} topologies, more than the limit "
            f"{limit}: lower explore.max_springs (--max-springs), list fewer explore.candidates, or raise "
            "explore.max_topologies"
        )
    return [
        combination
        for size in range(1, min(max_springs, count) + 1)
        for combination in itertools.combinations(range(count), size)
    ]


class SpatialTest:
    """The spatial reachability proofs (:class:`~springbalance.design.exact.SpatialReachability`) on a study's
    candidates: the same :meth:`verdict` as :class:`Reachability`."""

    def __init__(self, mechanism: Mechanism, candidates: Sequence[Candidate]):
        self.proofs = SpatialReachability(mechanism)
        self.pairs = [(c.a, c.b) for c in candidates]
        built = synthesize_spatial(mechanism, allowed=self.pairs)
        if built.exact:
            pairs = ", ".join(f"{a}→{b}" + (f" ×{n}" if n > 1 else "") for (a, b), n in built.pairs.items())
            #: what the construction of docs/model.md §9.1 gives on these candidates' pairs
            self.construction = (
                f"by construction {len(built.springs)} springs balance exactly on {pairs} "
                "(anchors not fitted to the boxes)"
            )
        else:
            missing = ", ".join(f"{a}→{b}" for a, b in built.missing)
            self.construction = (
                f"the construction of exact balance needs springs on pairs that are not candidates: {missing}"
            )

    def verdict(self, topology: Sequence[int]) -> Verdict | None:
        """None when exact balance may be reached; else why not."""
        found = self.proofs.verdict([self.pairs[index] for index in topology])
        return Verdict("unreachable", found.reason) if found.unreachable else None


def reachability(
    mechanism: Mechanism, candidates: Sequence[Candidate], law: str
) -> tuple[Reachability | SpatialTest | None, str]:
    """The reachability test when it applies (planar, else spatial), and a sentence saying which."""
    if law != "zero_free_length":
        return None, f"reachability test not applied: it is for zero-free-length springs (the study's law is {law!r})"
    try:
        return Reachability(mechanism, candidates), "reachability test applied (planar chain, zero-free-length springs)"
    except InputError as planar:
        try:
            test = SpatialTest(mechanism, candidates)
            return test, (
                "spatial reachability test applied (revolute joints, zero-free-length springs: gravity terms no "
                f"spring reaches, outermost pairs short of springs); {test.construction}"
            )
        except InputError as spatial:
            return None, f"reachability test not applied: {planar}; {spatial}"
