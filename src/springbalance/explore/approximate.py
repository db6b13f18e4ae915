r"""The best approximate design of a spring count that pruning leaves unsolved.

Pruning (:mod:`springbalance.explore.topology`) skips the topologies that cannot balance exactly. When
it skips *every* topology of a spring count (the three-link chain needs three zero-free-length
springs: every one- and two-spring topology is proven unreachable), the study would say nothing of
what one spring fewer costs. So, per such count, it solves the ``approximate`` pruned topologies
(``explore.approximate``, default :data:`DEFAULT`, a small bound) that the reachability test ranks
highest, and reports the best as that count's approximate design.

**The ranking** (no solve): a topology whose springs reach more of the gravity blocks
:math:`G_{0j}` can cancel more of the weight moments, so it comes first; ties go to the one that reaches
more blocks of the stiffness matrix in all, then to the enumeration's order. It is a heuristic: the best
of the solved few is the count's best approximate design *found*, not proven the best of the count.
"""

from __future__ import annotations

from typing import Sequence

from springbalance.explore.topology import Reachability, SpatialTest, Verdict

#: pruned topologies solved per spring count that pruning leaves without a topology to solve
DEFAULT = 3


def coverage(test: Reachability, topology: Sequence[int]) -> tuple[int, int]:
    """(loaded gravity blocks reached, blocks reached) by the springs of ``topology``: larger ranks first."""
    reached: set[tuple[int, int]] = set()
    for index in topology:
        reached |= test.reached(test.ends[index])
    return sum(1 for j in test.loaded if (0, j) in reached), len(reached)


def approximate_topologies(
    topologies: Sequence[tuple[int, ...]],
    verdicts: dict[tuple[int, ...], Verdict],
    test: Reachability | SpatialTest | None,
    limit: int,
) -> list[tuple[int, ...]]:
    """The pruned topologies to solve for an approximate design: per spring count of which every topology is
    pruned, the ``limit`` that :func:`coverage` ranks highest (the planar test), or the first ``limit`` in
    enumeration order (the spatial test, which has no ranking; none without a reachability test)."""
    if test is None or limit <= 0:
        return []
    chosen: list[tuple[int, ...]] = []
    for count in sorted({len(topology) for topology in topologies}):
        level = [topology for topology in topologies if len(topology) == count]
        if any(topology not in verdicts for topology in level):
            continue  # the count has a topology to solve: its best design is an exact attempt
        ranked = (
            sorted(level, key=lambda topology: tuple(-value for value in coverage(test, topology)))
            if isinstance(test, Reachability)
            else level
        )
        chosen.extend(ranked[:limit])
    return chosen


def why_not(count: int, candidates: int, limit: int, pruned: int) -> str:
    """Why a spring count has no design: too few candidates, or every topology pruned with ``limit`` 0."""
    if count > candidates:
        return f"only {candidates} candidate(s): no topology of {count} springs"
    if limit <= 0:
        return (
            f"all {pruned} topologies pruned; explore.approximate is 0 "
            "(set it ≥ 1 to solve the best few for an approximate design)"
        )
    return "no topology of this count was solved (see Not solved)"
