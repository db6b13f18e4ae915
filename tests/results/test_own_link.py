"""The ``inside_own_link`` warning: a spring whose centre line runs inside its own anchor link.

The arm is urdf/two_link_planar_collision.urdf (link1: box 0.5×0.04×0.04 m centred 0.25 m along x;
link2: box 0.4×0.03×0.03 m centred 0.2 m along x; both joints about (0, -1, 0)). The expected depths
follow from those boxes: a centre line along a box's axis lies half the box's thickness deep inside it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from flag_helpers import fixed_design
from springbalance.results.flags import inside_own_link_flags
from springbalance.results.own_link import OWN_STRETCH, inside_own_link

URDF = Path(__file__).resolve().parents[2] / "urdf"
LINK1_HALF_THICKNESS, LINK2_HALF_THICKNESS = 0.02, 0.015  # [m]


@pytest.fixture(scope="module")
def arm():
    return sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")


design = fixed_design


def test_a_spring_along_both_links_runs_inside_each_of_them(arm):
    # from link1 (0.1, 0, 0) to link2 (0.2, 0, 0): at the straight pose it lies on the links' common axis,
    # inside link1 from x = 0.1 to 0.5 and inside link2 from 0.5 to 0.7 (world x)
    spring = sb.ExtensionSpring(
        sb.Anchor("link1", [0.1, 0, 0]), sb.Anchor("link2", [0.2, 0, 0]), "along", stiffness=100.0, free_length=0.05
    )
    result = design(arm, [spring], [[0.3, 1.2], [0.0, 0.0]])
    found = {(item.spring, item.end): item for item in inside_own_link(result)}
    assert set(found) == {("along", "a"), ("along", "b")}
    a, b = found[("along", "a")], found[("along", "b")]
    assert a.body == "link1" and b.body == "link2"
    # deepest at the straight pose, half the box's thickness deep (the way out is sideways)
    assert a.pose == {"shoulder": 0.0, "elbow": 0.0} and a.sample == 1
    assert a.depth == pytest.approx(LINK1_HALF_THICKNESS, abs=1e-6)
    assert b.depth == pytest.approx(LINK2_HALF_THICKNESS, abs=1e-6)
    flags = inside_own_link_flags(result)
    assert [flag.kind for flag in flags] == ["inside_own_link"] * 2
    assert "20.0 mm deep" in flags[0].message and "'link1'" in flags[0].message
    assert any(flag.kind == "inside_own_link" for flag in result.warnings())


def test_a_spring_that_leaves_its_link_outward_is_not_flagged(arm):
    # from the middle of link1's axis straight up to a ground point 0.3 m above: it leaves the box through
    # its top face 20 mm out, within the anchor's own stretch (20 mm + 10 mm radius + 3 mm)
    spring = sb.ExtensionSpring(
        sb.Anchor("link1", [0.25, 0, 0]), sb.Anchor("universe", [0.25, 0, 0.3]), "up", stiffness=100.0, free_length=0.05
    )
    poses = [[0.0, 0.0], [0.2, 0.5], [-0.2, -0.5]]
    assert LINK1_HALF_THICKNESS + 0.01 + OWN_STRETCH > LINK1_HALF_THICKNESS / np.cos(0.2)
    result = design(arm, [spring], poses)
    assert inside_own_link(result) == []
    assert not any(flag.kind == "inside_own_link" for flag in result.warnings())


def test_without_collision_geometry_nothing_is_checked():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    spring = sb.ExtensionSpring(
        sb.Anchor("link1", [0.1, 0, 0]), sb.Anchor("link2", [0.2, 0, 0]), "along", stiffness=100.0, free_length=0.05
    )
    assert inside_own_link(design(mechanism, [spring], [[0.0, 0.0]])) == []
