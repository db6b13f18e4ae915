"""Spring topologies (springbalance.explore.topology): counts and reachability verdicts derived by hand.

Counting: the topologies of ``c`` candidates with at most ``s`` springs are the subsets of 1 … s
of them, ``Σ_{k=1}^{min(s,c)} C(c, k)``. Reachability (docs/model.md §9, zero-free-length
springs on a planar chain of ``n`` bodies, the ground included): exact balance needs
``⌈n(n−1)/4⌉`` springs, a spring from the ground to body ``j`` or beyond for each weight block
``K_0j``, and every block between moving bodies reached by two springs or none. So a single
pendulum (n = 2) balances exactly with one ground spring (``k a b = m g c``), while a chain of
two or more links with springs only between neighbours never can.
"""

from __future__ import annotations

from math import comb
from pathlib import Path

import pytest

from springbalance.errors import InputError
from springbalance.explore.candidates import Candidate, auto_candidates
from springbalance.explore.topology import Reachability, enumerate_topologies, reachability
from springbalance.model.mechanism import Mechanism

URDF = Path(__file__).resolve().parents[2] / "urdf"
BOX = ((-0.1, -0.1, -0.1), (0.1, 0.1, 0.1))


def _candidates(*pairs: tuple[str, str]) -> list[Candidate]:
    return [Candidate(a, b, BOX, BOX, 1) for a, b in pairs]


@pytest.mark.parametrize(
    ("count", "max_springs", "expected"), [(1, 1, 1), (3, 1, 3), (4, 2, 4 + 6), (6, 3, 6 + 15 + 20), (3, 5, 3 + 3 + 1)]
)
def test_topologies_are_the_subsets_of_up_to_max_springs_candidates(count, max_springs, expected):
    topologies = enumerate_topologies(count, max_springs)
    assert len(topologies) == expected == sum(comb(count, k) for k in range(1, min(count, max_springs) + 1))
    assert len(set(topologies)) == len(topologies)  # each set once, no orderings
    assert all(list(t) == sorted(set(t)) for t in topologies)
    assert [len(t) for t in topologies] == sorted(len(t) for t in topologies)  # fewer springs first


@pytest.mark.parametrize("bad", [0, -1, True, 1.5])
def test_max_springs_must_be_a_positive_integer(bad):
    with pytest.raises(InputError, match="max_springs"):
        enumerate_topologies(3, bad)


def test_a_single_pendulum_with_one_ground_spring_may_balance_exactly():
    pendulum = Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    test = Reachability(pendulum, _candidates(("universe", "link1")))
    assert test.verdict((0,)) is None


def test_the_three_link_chain_of_neighbours_is_unreachable():
    chain = Mechanism.from_urdf(URDF / "three_link_planar.urdf")
    candidates = auto_candidates(chain, span=2)
    labels = [c.label for c in candidates]
    assert labels == ["universe→link1", "universe→link2", "universe→link3", "link1→link2", "link2→link3", "link1→link3"]
    test = Reachability(chain, candidates)
    index = {label: i for i, label in enumerate(labels)}
    # n = 4 bodies: n(n-1) = 12 conditions need ⌈12/4⌉ = 3 springs
    assert test.verdict((index["universe→link2"], index["universe→link3"])).kind == "unreachable"
    neighbours = test.verdict(tuple(sorted(index[k] for k in ("universe→link1", "link1→link2", "link2→link3"))))
    assert neighbours.kind == "unreachable" and "K_02" in neighbours.reason
    # ground→link2, ground→link3, link1→link3: every weight block reached, every other block twice
    exact = tuple(sorted(index[k] for k in ("universe→link2", "universe→link3", "link1→link3")))
    assert test.verdict(exact) is None


def test_two_links_verdicts():
    arm = Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    candidates = _candidates(("universe", "link1"), ("universe", "link2"), ("link1", "link2"))
    test = Reachability(arm, candidates)
    # n = 3: ⌈6/4⌉ = 2 springs at least
    assert test.verdict((1,)).kind == "unreachable"
    # no spring from the ground reaches link2's weight block K_02
    assert test.verdict((0, 2)).kind == "unreachable"
    # ground→link1 + ground→link2: block K_12 is reached by ground→link2 alone: degenerate
    assert test.verdict((0, 1)).kind == "degenerate"
    # ground→link2 + link1→link2: K_01 and K_02 are weight blocks, K_12 is reached twice
    assert test.verdict((1, 2)) is None


def test_the_test_applies_to_zero_free_length_springs_only():
    arm = Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    candidates = _candidates(("universe", "link2"), ("link1", "link2"))
    test, note = reachability(arm, candidates, "extension")
    assert test is None and "zero-free-length" in note
    test, note = reachability(arm, candidates, "zero_free_length")
    assert isinstance(test, Reachability) and note.startswith("reachability test applied")
