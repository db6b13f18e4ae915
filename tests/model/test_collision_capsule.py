"""The capsule a clearance check builds around a spring's segment (springbalance.model.collision.capsule)."""

import coal
import numpy as np
import pytest

from springbalance.model.collision import capsule, segment_distances

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


def test_segment_distances_are_coals_capsule_distances_and_no_more_than_any_two_points():
    """Between random segments (some of zero or tiny length, some parallel), all at once: coal's distance of two
    capsules of radius 0, and at most the least distance of points sampled along both."""
    rng = np.random.default_rng(0)
    n = 2000
    lengths = rng.choice([0.0, 1e-3, 1.0, 3.0], size=(n, 2, 1))
    p1, p2 = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    q1, q2 = p1 + lengths[:, 0] * rng.normal(size=(n, 3)), p2 + lengths[:, 1] * rng.normal(size=(n, 3))
    parallel = rng.random(n) < 0.1
    q2[parallel] = p2[parallel] + (q1[parallel] - p1[parallel]) * rng.normal(size=(int(parallel.sum()), 1))
    found = segment_distances(p1, q1, p2, q2)
    request = coal.DistanceRequest()
    for i in range(n):
        first, second = capsule(p1[i], q1[i], 1e-9), capsule(p2[i], q2[i], 1e-9)
        expected = coal.distance(*first, *second, request, coal.DistanceResult()) + 2e-9
        assert found[i] == pytest.approx(expected, abs=1e-9)
    along = np.linspace(0.0, 1.0, 101)[:, None]
    for i in range(0, n, 20):
        a, b = p1[i] + along * (q1[i] - p1[i]), p2[i] + along * (q2[i] - p2[i])
        assert found[i] <= np.min(np.linalg.norm(a[:, None] - b[None], axis=-1)) + 1e-12


def test_the_placements_of_many_segments_at_once_are_each_capsules_bit_for_bit():
    """A clearance check takes the capsules of all its poses at once (capsule_placements) and makes coal's objects
    of each (placed_capsule): the same shape and placement as capsule() of that segment alone, bit for bit, for
    segments along every axis and a point segment (a sphere)."""
    from springbalance.model.collision import capsule_placements, placed_capsule

    rng = np.random.default_rng(7)
    starts = rng.normal(size=(2000, 3)) * 0.3
    ends = starts + rng.normal(size=(2000, 3)) * rng.uniform(0.0, 0.5, size=(2000, 1))
    for index, (start, end) in enumerate(SEGMENTS):
        starts[index], ends[index] = start, end
    ends[len(SEGMENTS)] = starts[len(SEGMENTS)]  # a point
    lengths, centres, rotations = capsule_placements(starts, ends)
    for index in range(len(starts)):
        shape, placement = capsule(starts[index], ends[index], 0.02)
        batched, batched_placement = placed_capsule(0.02, lengths[index], centres[index], rotations[index])
        assert type(batched) is type(shape)
        assert np.array_equal(batched_placement.getRotation(), placement.getRotation())
        assert np.array_equal(batched_placement.getTranslation(), placement.getTranslation())
        assert getattr(batched, "halfLength", None) == getattr(shape, "halfLength", None)
    assert isinstance(placed_capsule(0.02, lengths[len(SEGMENTS)], centres[0], rotations[0])[0], coal.Sphere)
