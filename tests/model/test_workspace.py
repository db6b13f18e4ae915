"""Workspace sampling: sizes, ranges, degrees, couplings, determinism, rejected input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf"
SHOULDER = (-np.pi / 2, np.pi / 2)  # URDF range of two_link_planar's shoulder [rad]
ELBOW = (-5 * np.pi / 6, 5 * np.pi / 6)  # and of its elbow (±150°)


@pytest.fixture(scope="module")
def arm():
    return sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")


def _coupling():
    return sb.Coupling.parse("elbow - shoulder", -60, 0, degrees=True)


def _assert_coupled(arm, values):
    difference = values[:, arm.joint("elbow").index_v] - values[:, arm.joint("shoulder").index_v]
    assert np.all(difference >= np.deg2rad(-60) - 1e-12)
    assert np.all(difference <= 1e-12)


def _assert_in_ranges(arm, values, shoulder=SHOULDER, elbow=ELBOW):
    s, e = values[:, arm.joint("shoulder").index_v], values[:, arm.joint("elbow").index_v]
    assert np.all((s >= shoulder[0]) & (s <= shoulder[1]))
    assert np.all((e >= elbow[0]) & (e <= elbow[1]))


# ---------------------------------------------------------------------- grid
def test_grid_size_and_urdf_ranges(arm):
    workspace = sb.Workspace.grid(arm, 7)
    assert workspace.size == len(workspace) == 49
    assert workspace.joint_values.shape == (49, 2)
    assert workspace.ordered
    s, e = workspace.joint_values.T
    assert np.allclose(np.unique(s), np.linspace(*SHOULDER, 7), rtol=0, atol=1e-15)
    assert np.allclose(np.unique(e), np.linspace(*ELBOW, 7), rtol=0, atol=1e-15)
    # Every combination appears once.
    assert len({tuple(row) for row in workspace.joint_values}) == 49


def test_grid_counts_per_joint_and_held_joint(arm):
    workspace = sb.Workspace.grid(arm, {"shoulder": 3, "elbow": 5})
    assert workspace.size == 15
    assert len(np.unique(workspace.joint_values[:, 0])) == 3
    assert len(np.unique(workspace.joint_values[:, 1])) == 5
    held = sb.Workspace.grid(arm, 9, ranges={"elbow": 0.4})  # zero-width range: one value
    assert held.size == 9
    assert np.all(held.joint_values[:, 1] == 0.4)


def test_grid_ranges_in_degrees(arm):
    workspace = sb.Workspace.grid(arm, 3, ranges={"shoulder": (-30, 30), "elbow": (0, 90)}, degrees=True)
    assert np.allclose(np.unique(workspace.joint_values[:, 0]), np.deg2rad([-30, 0, 30]), rtol=0, atol=1e-15)
    assert np.allclose(np.unique(workspace.joint_values[:, 1]), np.deg2rad([0, 45, 90]), rtol=0, atol=1e-15)


def test_grid_with_coupling_keeps_exactly_the_admissible_points(arm):
    workspace = sb.Workspace.grid(arm, 13, couplings=[_coupling()])
    _assert_coupled(arm, workspace.joint_values)
    s, e = np.meshgrid(np.linspace(*SHOULDER, 13), np.linspace(*ELBOW, 13), indexing="ij")
    admissible = (e - s >= np.deg2rad(-60) - 1e-12) & (e - s <= 1e-12)
    assert workspace.size == int(np.sum(admissible))
    assert 0 < workspace.size < 169


# ---------------------------------------------------------------------- sampled
@pytest.mark.parametrize("method", ["sobol", "random"])
def test_sampled_size_ranges_and_determinism(arm, method):
    build = getattr(sb.Workspace, method)
    first = build(arm, 100, seed=7)
    assert first.size == 100
    assert not first.ordered
    _assert_in_ranges(arm, first.joint_values)
    # Samples spread over the ranges (not all in a corner).
    assert np.ptp(first.joint_values[:, 0]) > 0.8 * (SHOULDER[1] - SHOULDER[0])
    assert np.ptp(first.joint_values[:, 1]) > 0.8 * (ELBOW[1] - ELBOW[0])
    np.testing.assert_array_equal(build(arm, 100, seed=7).joint_values, first.joint_values)
    assert not np.array_equal(build(arm, 100, seed=8).joint_values, first.joint_values)


@pytest.mark.parametrize("method", ["sobol", "random"])
def test_sampled_ranges_in_degrees(arm, method):
    workspace = getattr(sb.Workspace, method)(arm, 64, ranges={"shoulder": (10, 20)}, degrees=True, seed=1)
    _assert_in_ranges(arm, workspace.joint_values, shoulder=(np.deg2rad(10), np.deg2rad(20)))


@pytest.mark.parametrize("method", ["sobol", "random"])
def test_sampled_coupling_respected_by_every_sample(arm, method):
    workspace = getattr(sb.Workspace, method)(arm, 200, couplings=[_coupling()], seed=3)
    assert workspace.size == 200
    _assert_coupled(arm, workspace.joint_values)
    _assert_in_ranges(arm, workspace.joint_values)
    # The coupling is a band, not a line: the difference spans most of [-60°, 0°].
    difference = workspace.joint_values[:, 1] - workspace.joint_values[:, 0]
    assert np.ptp(difference) > np.deg2rad(50)


def test_coupling_parse():
    coupling = _coupling()
    assert dict(coupling.coefficients) == {"elbow": 1.0, "shoulder": -1.0}
    assert coupling.bounds() == pytest.approx((-np.pi / 3, 0.0))
    scaled = sb.Coupling.parse("2*elbow + 0.5*shoulder", -1, 1)
    assert dict(scaled.coefficients) == {"elbow": 2.0, "shoulder": 0.5}
    with pytest.raises(sb.InputError, match="coupling"):
        sb.Coupling.parse("elbow -* shoulder", 0, 1)


def test_coupling_in_radians(arm):
    coupling = sb.Coupling.parse("elbow + shoulder", 0.0, 0.5)
    workspace = sb.Workspace.random(arm, 50, couplings=[coupling], seed=0)
    total = workspace.joint_values.sum(axis=1)
    assert np.all((total >= -1e-12) & (total <= 0.5 + 1e-12))


# ---------------------------------------------------------------------- explicit arrays
def test_from_array_radians_and_degrees(arm):
    rows = [[10.0, -20.0], [30.0, 45.0]]
    degrees = sb.Workspace.from_array(arm, rows, degrees=True)
    np.testing.assert_allclose(degrees.joint_values, np.deg2rad(rows), rtol=1e-15)
    assert degrees.ordered
    radians = sb.Workspace.from_array(arm, np.deg2rad(rows), ordered=False)
    np.testing.assert_allclose(radians.joint_values, degrees.joint_values, rtol=1e-15)
    assert not radians.ordered


# ---------------------------------------------------------------------- rejected input
@pytest.mark.parametrize("method", ["grid", "sobol", "random"])
def test_lower_above_upper_rejected(arm, method):
    with pytest.raises(sb.InputError, match="shoulder"):
        getattr(sb.Workspace, method)(arm, 8, ranges={"shoulder": (1.0, 0.5)})
    with pytest.raises(sb.InputError, match="elbow"):
        getattr(sb.Workspace, method)(arm, 8, ranges={"elbow": (30, -30)}, degrees=True)


@pytest.mark.parametrize("method", ["grid", "sobol", "random"])
@pytest.mark.parametrize("bounds", [(np.nan, 1.0), (0.0, np.nan), (-np.inf, 0.0)])
def test_nan_and_infinite_ranges_rejected(arm, method, bounds):
    with pytest.raises(sb.InputError, match="shoulder"):
        getattr(sb.Workspace, method)(arm, 8, ranges={"shoulder": bounds})


def test_coupling_lower_above_upper_rejected(arm):
    backwards = sb.Coupling.parse("elbow - shoulder", 0, -60, degrees=True)
    for build in (sb.Workspace.grid, sb.Workspace.sobol, sb.Workspace.random):
        with pytest.raises(sb.InputError, match="lower > upper"):
            build(arm, 8, couplings=[backwards])


def test_coupling_excluding_everything_rejected(arm):
    impossible = sb.Coupling.parse("elbow - shoulder", 20, 21, degrees=False)  # |elbow - shoulder| ≤ 4.19 rad
    with pytest.raises(sb.InputError, match="coupling"):
        sb.Workspace.grid(arm, 8, couplings=[impossible])
    with pytest.raises(sb.InputError, match="coupling"):
        sb.Workspace.sobol(arm, 8, couplings=[impossible])


def test_unknown_joint_in_range_or_coupling_named(arm):
    with pytest.raises(sb.InputError, match="wrist"):
        sb.Workspace.grid(arm, 4, ranges={"wrist": (0, 1)})
    with pytest.raises(sb.InputError, match="knee"):
        sb.Workspace.sobol(arm, 4, couplings=[sb.Coupling.parse("knee - shoulder", 0, 1)])
    with pytest.raises(sb.InputError, match="wrist"):
        sb.Workspace.grid(arm, {"wrist": 3})


def test_bad_arrays_and_counts_rejected(arm):
    with pytest.raises(sb.InputError, match="not finite"):
        sb.Workspace.from_array(arm, [[0.0, np.nan]])
    with pytest.raises(sb.InputError, match="shape"):
        sb.Workspace.from_array(arm, [[0.0, 0.1, 0.2]])
    with pytest.raises(sb.InputError):
        sb.Workspace.grid(arm, 0)
    with pytest.raises(sb.InputError):
        sb.Workspace.sobol(arm, 0)
