"""Spatial pruning and the size limit of a study (springbalance.explore.topology), derived by hand.

On the UR5 (example-robot-data), wrist 3 (0.1879 kg) sits 0.09465 m out along wrist 2's axis, which
wrist 1 turns; so gravity's potential has a term in the lift, elbow and wrist-1 angles together
(docs/model.md §9.1). A zero-free-length spring's potential depends only on the joints between its two
bodies, so a topology none of whose springs crosses the lift, the elbow and wrist 1 can never balance the
UR5 exactly. The topologies of ``c`` candidates with at most ``s`` springs number
``Σ_{k=1}^{min(s,c)} C(c, k)``.
"""

from __future__ import annotations

from math import comb

import pytest

from springbalance.errors import InputError
from springbalance.explore.candidates import auto_candidates
from springbalance.explore.study import Study
from springbalance.explore.topology import SpatialTest, count_topologies, reachability
from springbalance.model.mechanism import Mechanism


@pytest.fixture(scope="module")
def ur5():
    mechanism = Mechanism.from_robot("ur5")
    return mechanism, auto_candidates(mechanism)


def test_a_spatial_arm_gets_the_spatial_test(ur5):
    mechanism, candidates = ur5
    test, note = reachability(mechanism, candidates, "zero_free_length")
    assert isinstance(test, SpatialTest) and note.startswith("spatial reachability test applied")


def test_the_note_says_what_the_construction_gives_on_the_candidates(ur5):
    mechanism, _ = ur5
    wide = auto_candidates(mechanism, span=6)  # every pair of bodies along the chain
    test = SpatialTest(mechanism, wide)
    assert test.construction.startswith("by construction") and "balance exactly on" in test.construction
    used = test.construction.split("balance exactly on ", 1)[1].split(" (anchors")[0].split(", ")
    assert {label.split(" ×")[0] for label in used} <= {c.label for c in wide}
    only_ground = [c for c in wide if c.a == "universe"][:2]  # the ground to the pan and lift links only
    assert "not candidates" in SpatialTest(mechanism, only_ground).construction


def test_springs_that_miss_wrist_1_are_proven_unreachable(ur5):
    mechanism, candidates = ur5
    test = SpatialTest(mechanism, candidates)
    index = {c.label: i for i, c in enumerate(candidates)}
    short = test.verdict([index["universe→forearm_link"], index["shoulder_link→upper_arm_link"]])
    assert short is not None and short.kind == "unreachable" and "wrist_1_joint" in short.reason
    elbow_wrist = test.verdict([index["upper_arm_link→wrist_1_link"]])  # crosses the elbow and wrist 1, not the lift
    assert elbow_wrist is not None and elbow_wrist.kind == "unreachable"
    assert test.verdict([index["universe→wrist_1_link"]]) is None  # crosses pan, lift, elbow, wrist 1


def test_the_size_of_a_study_is_counted_before_it_is_enumerated():
    assert count_topologies(15, 10) == sum(comb(15, k) for k in range(1, 11)) == 30826
    record = {
        "mechanism": {"robot": "ur5"},
        "workspace": {"kind": "sobol", "n": 16, "seed": 0},
        "explore": {"candidates": "auto", "max_springs": 10},
    }
    with pytest.raises(InputError, match="30826 topologies, more than the limit 20000"):
        Study(record, ".", "ur5.yaml")
    with pytest.raises(InputError, match="explore.max_topologies must be an integer"):
        Study({**record, "explore": {**record["explore"], "max_topologies": 0}}, ".", "ur5.yaml")
    study = Study({**record, "explore": {**record["explore"], "max_springs": 2}}, ".", "ur5.yaml")
    summary = study.summary()
    assert summary["topologies"] == 15 + comb(15, 2)
    assert summary["tasks"] == summary["topologies"] - len(summary["unreachable"]) - len(summary["degenerate"])
