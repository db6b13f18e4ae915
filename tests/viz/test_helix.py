"""The drawing's pieces: the helix geometry and the colour scale of the tensions."""

from __future__ import annotations

import numpy as np
import pytest

from springbalance.viz import colors, helix


# ---------------------------------------------------------------------- helix geometry
def test_helix_centerline_has_the_coils_and_ends_on_the_axis():
    line = helix.helix_centerline(coils=7, coil_radius=0.02, lead=0.1, points_per_coil=30)
    np.testing.assert_array_equal(line[0], [0, 0, 0])
    np.testing.assert_array_equal(line[-1], [0, 0, 1])
    coil = line[1:-1]
    np.testing.assert_allclose(np.hypot(coil[:, 0], coil[:, 1]), 0.02, rtol=1e-12)  # the coil radius
    assert np.all(np.diff(line[:, 2]) > 0)  # it always advances
    turns = np.unwrap(np.arctan2(coil[:, 1], coil[:, 0]))
    assert (turns[-1] - turns[0]) / (2 * np.pi) == pytest.approx(7.0)  # 7 coils
    assert coil[0, 2] == pytest.approx(0.1) and coil[-1, 2] == pytest.approx(0.9)  # hooks of 10 % each


def test_helix_tube_is_a_wire_around_the_centerline():
    line = helix.helix_centerline(5, 0.03, 0.08, 16)
    vertices, faces = helix.helix_tube(line, wire_radius=0.004, reference_length=0.4, sides=6)
    np.testing.assert_array_equal(vertices[0], [0, 0, 0])  # start cap centre = start of the helix
    np.testing.assert_array_equal(vertices[-1], [0, 0, 1])  # end cap centre = end of the helix
    assert faces.min() == 0 and faces.max() == len(vertices) - 1
    # in metres (axial coordinate times the reference length), every ring vertex is one wire radius
    # from its centre-line point
    rings = vertices[1:-1].reshape(len(line), 6, 3) * [1, 1, 0.4]
    distance = np.linalg.norm(rings - (line * [1, 1, 0.4])[:, None, :], axis=2)
    np.testing.assert_allclose(distance, 0.004, rtol=1e-9)


def test_spring_rotation_maps_the_axis_onto_the_spring():
    rng = np.random.default_rng(0)
    for _ in range(20):
        direction, side = rng.normal(size=3), rng.normal(size=3)
        rotation = helix.spring_rotation(direction, side)
        np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
        assert np.linalg.det(rotation) == pytest.approx(1.0)
        np.testing.assert_allclose(rotation[:, 2], direction / np.linalg.norm(direction), atol=1e-12)
    # a side vector along the spring falls back to another axis instead of failing
    rotation = helix.spring_rotation([0, 0, 2.0], [0, 0, 1.0])
    np.testing.assert_allclose(rotation[:, 2], [0, 0, 1], atol=1e-12)


# ---------------------------------------------------------------------- colour scale
def test_colour_scale_is_warm_for_tension_and_green_for_compression():
    scale = colors.ColorScale(200.0)
    assert scale.rgb(0.0) == colors.TENSION_STOPS[0][1]
    assert scale.rgb(200.0) == pytest.approx(colors.TENSION_STOPS[-1][1])
    assert scale.rgb(1e6) == pytest.approx(colors.TENSION_STOPS[-1][1])  # saturates
    assert scale.rgb(-200.0) == pytest.approx(colors.COMPRESSION_STOPS[-1][1])
    brightness = [sum(scale.rgb(t)) for t in np.linspace(0, 200, 11)]
    assert all(b1 > b2 for b1, b2 in zip(brightness, brightness[1:]))  # darker with more tension
    for t in (0.0, 50.0, 150.0):
        r, g, b = scale.rgb(t)
        assert r > max(g, b)  # warm (red leads; the dark end leans to raspberry, away from the clearance red)
    r, g, b = scale.rgb(-100.0)
    assert g > r and g > b  # green
    assert scale.css(200.0) == f"#{scale.hex(200.0):06x}" == "#8c0052"  # (0.55, 0, 0.32)
    legend = scale.legend_html(compression=True)
    assert "spring tension [N]" in legend and "-200" in legend and "200" in legend
