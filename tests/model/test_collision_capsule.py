"""The capsule a clearance check builds around a spring's segment (springbalance.model.collision.capsule)."""

import coal
import numpy as np
import pytest

from springbalance.model.collision import capsule

SEGMENTS = [
    ([0.1, 0.2, 0.3], [0.4, 0.1, 0.5]),
    ([0.0, 0.0, 0.0], [0.0, 0.0, -0.7]),  # along −z: the helper axis is x
    ([0.2, -0.1, 0.0], [0.9, -0.1, 0.0]),  # along x: the helper axis is y
    ([1.0, 1.0, 1.0], [1.0, 1.3, 1.0001]),
]


@pytest.mark.parametrize("start, end", SEGMENTS)
def test_the_capsule_lies_along_its_segment(start, end):
    start, end = np.array(start), np.array(end)
    shape, placement = capsule(start, end, 0.02)
    rotation, centre = placement.getRotation(), placement.getTranslation()
    assert rotation @ rotation.T == pytest.approx(np.eye(3), abs=1e-14)
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-14)
    axis = (end - start) / np.linalg.norm(end - start)
    assert rotation[:, 2] == pytest.approx(axis, abs=1e-15)  # its local z along the segment
    assert centre == pytest.approx((start + end) / 2, abs=1e-15)
    assert 2 * shape.halfLength == pytest.approx(np.linalg.norm(end - start), abs=1e-15)
    assert shape.radius == 0.02


def test_its_distance_to_a_sphere_is_the_closed_form():
    """Distance from the capsule (0,0,0)–(1,0,0), radius 0.1, to a unit sphere at (0.5, 2, 0): 2 − 0.1 − 1."""
    shape, placement = capsule(np.zeros(3), np.array([1.0, 0.0, 0.0]), 0.1)
    request = coal.DistanceRequest()
    distance = coal.distance(
        shape,
        placement,
        coal.Sphere(1.0),
        coal.Transform3s(np.eye(3), np.array([0.5, 2.0, 0.0])),
        request,
        coal.DistanceResult(),
    )
    assert distance == pytest.approx(0.9, abs=1e-9)


def test_a_point_segment_is_a_sphere():
    shape, placement = capsule(np.ones(3), np.ones(3), 0.03)
    assert isinstance(shape, coal.Sphere) and shape.radius == 0.03
    assert placement.getTranslation() == pytest.approx(np.ones(3))
