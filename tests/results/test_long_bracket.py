"""The ``long_bracket`` warning: an anchor that stands far off its link needs a bracket the design leaves out.

The arm is urdf/two_link_planar_collision.urdf (link1: box 0.5 × 0.04 × 0.04 m centred 0.25 m along x, its top
face at z = 0.02 m in link1's frame). The springs are fixed, so their tensions follow from their laws: a
zero-free-length spring of stiffness k between points d apart pulls with k·d.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from flag_helpers import fixed_design
from springbalance.results.brackets import BRACKET_WARNING
from springbalance.results.flags import long_bracket_flags

URDF = Path(__file__).resolve().parents[2] / "urdf"


@pytest.fixture(scope="module")
def arm():
    return sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")


def _spring(name: str, height: float) -> sb.ZeroFreeLengthSpring:
    """From the ground 0.5 m above the shoulder to link1's point 0.3 m along it, ``height`` [m] above its axis."""
    return sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0.3, 0, 0.5]), sb.Anchor("link1", [0.3, 0, height]), name, stiffness=200.0
    )


def test_an_anchor_far_off_its_link_is_flagged_with_its_bracket_and_load(arm):
    # at the horizontal pose the far anchor (0.3, 0, 0.12) is 0.38 m below the ground point: 200 N/m × 0.38 m = 76 N;
    # at 0.5 rad the spring is longer, so the largest tension is there
    poses = [[0.0, 0.0], [0.5, 0.0]]
    result = fixed_design(arm, [_spring("far", 0.12), _spring("near", 0.05)], poses)
    flags = long_bracket_flags(result)
    assert [flag.subject for flag in flags] == ["far"]  # "near" stands 30 mm off: below the 50 mm threshold
    assert 0.03 < BRACKET_WARNING < 0.10
    far = flags[0]
    assert far.kind == "long_bracket" and far.severity == "warning"
    assert "b stands 100 mm off link1" in far.message
    anchor = np.array([0.3 * np.cos(0.5) - 0.12 * np.sin(0.5), 0.3 * np.sin(0.5) + 0.12 * np.cos(0.5)])
    lengths = [np.hypot(0.0, 0.5 - 0.12), np.hypot(0.3 - anchor[0], 0.5 - anchor[1])]
    force = 200.0 * max(lengths)
    assert f"up to {force:.0f} N" in far.message
    assert f"{force * 0.10:.1f} N·m" in far.message
    assert "on: collision" in far.hint
    assert any(flag.kind == "long_bracket" for flag in result.warnings())


def test_no_bracket_warning_without_collision_geometry():
    plain = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    assert long_bracket_flags(fixed_design(plain, [_spring("far", 0.12)], [[0.0, 0.0]])) == []


def test_a_straight_bracket_through_another_link_must_go_round_it(arm):
    # link2's anchor 0.3 m behind the elbow: at elbow 0 its bracket runs back along link1's axis, inside link1's
    # box 20 mm from its nearest face (the box's half thickness)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0.3, 0, 0.5]), sb.Anchor("link2", [-0.3, 0, 0]), "behind", stiffness=100.0
    )
    (flag,) = long_bracket_flags(fixed_design(arm, [spring], [[0.0, 1.0], [0.0, 0.0]]))
    assert "b stands 300 mm off link2" in flag.message
    assert "the straight bracket at b passes through link1 at some poses (20 mm deep) and must go round it" in (
        flag.message
    )
