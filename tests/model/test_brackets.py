"""The bracket an anchor needs when it stands off its link (:mod:`springbalance.model.brackets`).

The arm is urdf/two_link_planar_collision.urdf: link1's collision box is 0.5 × 0.04 × 0.04 m centred at
(0.25, 0, 0) in link1's frame (x from 0 to 0.5 m, y and z within ±0.02 m). The expected lengths and feet
follow from the box alone.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.model.brackets import bracket, spring_brackets
from springbalance.model.collision import collision_geometry

URDF = Path(__file__).resolve().parents[2] / "urdf"


@pytest.fixture(scope="module")
def arm():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")
    return mechanism, collision_geometry(mechanism)


@pytest.mark.parametrize(
    "point, length, foot",
    [
        ([0.25, 0.0, 0.12], 0.10, [0.25, 0.0, 0.02]),  # above the top face
        ([0.6, 0.0, 0.0], 0.10, [0.5, 0.0, 0.0]),  # beyond the far end
        ([0.55, 0.0, 0.06], np.hypot(0.05, 0.04), [0.5, 0.0, 0.02]),  # off the far top edge
    ],
)
def test_a_bracket_reaches_from_the_nearest_surface_point_to_the_anchor(arm, point, length, foot):
    mechanism, geometry = arm
    held = bracket(mechanism, geometry, "link1", np.array(point))
    assert held is not None and held.body == "link1"
    assert held.length == pytest.approx(length, abs=1e-6)
    np.testing.assert_allclose(held.foot, foot, atol=1e-6)
    np.testing.assert_array_equal(held.anchor, point)


def test_no_bracket_on_the_surface_inside_the_link_or_on_the_ground(arm):
    mechanism, geometry = arm
    assert bracket(mechanism, geometry, "link1", np.array([0.25, 0.0, 0.01])) is None  # inside the box
    assert bracket(mechanism, geometry, "link1", np.array([0.25, 0.0, 0.02])) is None  # on its top face
    assert bracket(mechanism, geometry, "universe", np.array([0.0, 0.0, 0.5])) is None  # a ground anchor


def test_the_brackets_of_spring_records_by_spring_and_end(arm):
    mechanism, _ = arm
    records = [
        {"name": "s1", "a": {"body": "universe", "point": [0, 0, 0.3]}, "b": {"body": "link1", "point": [0.3, 0, 0.1]}},
        {"name": "s2", "a": {"body": "link1", "point": [0.1, 0, 0]}, "b": {"body": "link2", "point": [0.2, 0, 0.065]}},
        {"name": "twist", "joint": "elbow"},  # a torsional spring has no ends
    ]
    found = spring_brackets(mechanism, records)
    assert set(found) == {("s1", "b"), ("s2", "b")}
    assert found[("s1", "b")].length == pytest.approx(0.08, abs=1e-6)  # link1's top face at z = 0.02
    assert found[("s2", "b")].length == pytest.approx(0.05, abs=1e-6)  # link2's box: top face at z = 0.015
    plain = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")  # no collision geometry: nothing to measure
    assert spring_brackets(plain, records) == {}


def test_a_straight_bracket_through_another_link_is_found_where_it_passes_deepest(arm):
    """link2's anchor 0.3 m behind the elbow along link2's axis: its bracket runs from link2's end face at the
    elbow back along the arm. Straight (elbow 0) it lies on link1's axis inside link1's box, 20 mm from its
    nearest face (the half thickness); at elbow 90° it only touches link1's end face x = 0.5 m."""
    from springbalance.model.brackets import bracket_crossings

    mechanism, geometry = arm
    held = bracket(mechanism, geometry, "link2", np.array([-0.3, 0.0, 0.0]))
    assert held is not None and held.length == pytest.approx(0.3, abs=1e-6)
    np.testing.assert_allclose(held.foot, [0.0, 0.0, 0.0], atol=1e-6)
    configurations = np.array([[0.0, 1.0], [0.0, 0.0], [0.0, np.pi / 2]])  # shoulder, elbow [rad]
    crossings = bracket_crossings(mechanism, {"behind": held}, configurations)
    assert set(crossings) == {"behind"}
    assert crossings["behind"].link == "link1" and crossings["behind"].pose == 1
    assert crossings["behind"].depth == pytest.approx(0.02, abs=1e-6)
    above = bracket(mechanism, geometry, "link1", np.array([0.25, 0.0, 0.12]))
    assert bracket_crossings(mechanism, {"above": above}, configurations) == {}  # clear of link2 and the tool
