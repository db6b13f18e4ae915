"""Where a spring may go (springbalance.explore.candidates), checked against the URDFs by hand.

``two_link_planar_collision.urdf``: ``base`` (the ground) —shoulder→ ``link1`` —elbow→ ``link2``
—fixed→ ``tool``. Collision geometry (each in its link's frame): link1 a box 0.5 × 0.04 × 0.04 m
centred at (0.25, 0, 0), so its bounds are x ∈ [0, 0.5], y, z ∈ [−0.02, 0.02]; link2 a box
0.4 × 0.03 × 0.03 m centred at (0.2, 0, 0): x ∈ [0, 0.4], y, z ∈ [−0.015, 0.015]. The module's
promise: ``auto`` joins the ground to every moving body and every body to its descendants within
``span`` joints, one body per joint (``tool`` is welded to ``link2``), and each end's box is the
body's collision bounds grown by ``margin`` on every side; the ground's box (no geometry) is the
cube of half-width ``default`` about its origin.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from springbalance.errors import InputError
from springbalance.explore.candidates import auto_candidates, candidates_from_records
from springbalance.model.mechanism import Mechanism

URDF = Path(__file__).resolve().parents[2] / "urdf"
LINK1 = (np.array([0.0, -0.02, -0.02]), np.array([0.5, 0.02, 0.02]))  # collision bounds [m]
LINK2 = (np.array([0.0, -0.015, -0.015]), np.array([0.4, 0.015, 0.015]))


@pytest.fixture(scope="module")
def arm() -> Mechanism:
    return Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")


def test_auto_joins_the_ground_to_each_moving_body_and_neighbours_within_the_span(arm):
    candidates = auto_candidates(arm, span=2, margin=0.05, default=0.3)
    assert [c.label for c in candidates] == ["universe→link1", "universe→link2", "link1→link2"]
    assert [c.span for c in candidates] == [1, 2, 1]
    # a span of 1 still has link1 → link2 (one joint apart) and the ground to each body
    assert len(auto_candidates(arm, span=1)) == 3


def test_auto_boxes_are_the_collision_bounds_grown_by_the_margin(arm):
    margin = 0.05
    by_label = {c.label: c for c in auto_candidates(arm, span=2, margin=margin, default=0.3)}
    for label, end, bounds in (
        ("universe→link1", "b", LINK1),
        ("link1→link2", "a", LINK1),
        ("universe→link2", "b", LINK2),
        ("link1→link2", "b", LINK2),
    ):
        lower, upper = getattr(by_label[label], f"box_{end}")
        np.testing.assert_allclose(lower, bounds[0] - margin, atol=1e-12, err_msg=label)
        np.testing.assert_allclose(upper, bounds[1] + margin, atol=1e-12, err_msg=label)
        # the geometry lies inside the box, clear of each face by exactly the margin
        np.testing.assert_allclose(np.array(upper) - bounds[1], margin, atol=1e-12)
        np.testing.assert_allclose(bounds[0] - np.array(lower), margin, atol=1e-12)


def test_the_ground_end_is_the_default_cube_about_the_origin(arm):
    for candidate in auto_candidates(arm, span=2, margin=0.05, default=0.25)[:2]:
        assert candidate.a == "universe"
        assert candidate.box_a == ((-0.25, -0.25, -0.25), (0.25, 0.25, 0.25))


def test_a_body_without_collision_geometry_gets_the_default_cube():
    plain = Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    for candidate in auto_candidates(plain, span=2, margin=0.05, default=0.2):
        assert candidate.box_a == candidate.box_b == ((-0.2,) * 3, (0.2,) * 3)


def test_named_pairs_are_put_ground_side_first_and_welded_bodies_count_once(arm):
    (candidate,) = candidates_from_records(arm, [["link2", "link1"]], margin=0.0)
    assert (candidate.a, candidate.b, candidate.span) == ("link1", "link2", 1)
    np.testing.assert_allclose(candidate.box_b[1], LINK2[1], atol=1e-12)
    with pytest.raises(InputError, match="move as one body"):
        candidates_from_records(arm, [["link2", "tool"]])
    with pytest.raises(InputError, match=r"the same bodies as explore.candidates\[0\]"):
        candidates_from_records(arm, [["link1", "link2"], ["link1", "tool"]])
    with pytest.raises(InputError, match="unknown body 'link9'"):
        candidates_from_records(arm, [["universe", "link9"]])


def test_a_candidate_with_boxes_keeps_them():
    arm = Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    record = {
        "a": {"body": "universe", "box": {"lower": [-0.1, 0, 0], "upper": [0.1, 0, 0.2]}},
        "b": {"body": "link2", "box": {"lower": [0, 0, 0], "upper": [0.3, 0, 0]}},
    }
    (candidate,) = candidates_from_records(arm, [record])
    assert candidate.box_a == ((-0.1, 0.0, 0.0), (0.1, 0.0, 0.2))
    assert candidate.box_b == ((0.0, 0.0, 0.0), (0.3, 0.0, 0.0))
    assert candidate.span == 2
    assert candidate.anchors()[1] == {"body": "link2", "box": {"lower": [0.0, 0.0, 0.0], "upper": [0.3, 0.0, 0.0]}}
