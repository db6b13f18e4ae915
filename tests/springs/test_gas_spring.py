"""A gas spring balancing a link: the optimiser's peak-torque reduction against a brute-force
grid search over (F0, k, anchor).

urdf/single_link_r2.urdf (m = 1 kg, centre of mass at c = 0.25 m, angle theta from the
horizontal, g = 9.8), workspace theta in [0°, 60°]. A gas spring pushes from the ground
point G = (0.05, -0.05) m (x forward, z up, pivot at the origin) to the link point at
b ∈ [0.05, 0.3] m along the link; extended length l0 = 0.3 m, preload F0 ∈ [0, 100] N,
progression k ∈ [0, 1000] N/m, and it must stay compressed (L ≤ l0).

Closed form (independent of the library): the link point is p = b (cos θ, sin θ), the spring
length ``L = |p - G|``, ``dL/dθ = (p - G)·dp/dθ / L``, the push ``F0 + k (l0 - L)`` (tension
``-(F0 + k (l0 - L))``, docs/model.md §3.4), and the holding torque
``tau = m g c cos θ - (F0 + k (l0 - L)) dL/dθ`` (docs/model.md §4).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf"
A = 1.0 * 9.8 * 0.25  # m g c [N·m]
GROUND = np.array([0.05, -0.05])  # (x, z) [m]
L0 = 0.3  # extended length [m]
BOUNDS = {"preload": (0.0, 100.0), "stiffness": (0.0, 1000.0), "b": (0.05, 0.3)}


def holding_torque(theta, preload, stiffness, b):
    """tau(theta) for arrays of designs (broadcast over leading axes); +inf where L > l0."""
    preload, stiffness, b = (np.asarray(v, dtype=float)[..., None] for v in np.broadcast_arrays(preload, stiffness, b))
    px, pz = b * np.cos(theta), b * np.sin(theta)
    dx, dz = px - GROUND[0], pz - GROUND[1]
    length = np.hypot(dx, dz)
    rate = (dx * -pz + dz * px) / length  # dL/dθ [m/rad]
    tau = A * np.cos(theta) - (preload + stiffness * (L0 - length)) * rate
    return np.where(np.all(length <= L0, axis=-1, keepdims=True), tau, np.inf)


def grid_search(theta, points=(31, 21, 21)):
    """Brute force: a full grid over the bounds, then finer grids around the best point."""
    names = ("preload", "stiffness", "b")
    centre, width = None, None
    for stage, count in enumerate(points):
        axes = []
        for i, name in enumerate(names):
            low, high = BOUNDS[name]
            if stage:
                low, high = max(low, centre[i] - width[i]), min(high, centre[i] + width[i])
            axes.append(np.linspace(low, high, count))
        grids = np.meshgrid(*axes, indexing="ij")
        peaks = np.max(np.abs(holding_torque(theta, *grids)), axis=-1)
        best = np.unravel_index(np.argmin(peaks), peaks.shape)
        centre = [grid[best] for grid in grids]
        width = [2 * (axis[1] - axis[0]) for axis in axes]
    return float(peaks[best]), dict(zip(names, centre))


def test_gas_spring_peak_reduction_matches_grid_search():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r2.urdf", gravity=9.8)
    workspace = sb.Workspace.grid(mechanism, 121, ranges={"theta": (0, 60)}, degrees=True)
    theta = workspace.joint_values[:, 0]
    gas = sb.GasSpring(
        sb.Anchor("universe", (GROUND[0], 0, GROUND[1])),
        sb.Anchor("link1", sb.Segment((0.05, 0, 0), (0.3, 0, 0))),
        stiffness=sb.Free(*BOUNDS["stiffness"]),
        preload=sb.Free(*BOUNDS["preload"]),
        free_length=L0,
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [gas], objective="peak"), starts=8)
    values = result.spring("s1")
    design = (values["preload"], values["stiffness"], values["b"]["point"][0])
    # the library's torque is the closed form's
    np.testing.assert_allclose(result.evaluation.tau[:, 0], holding_torque(theta, *design), rtol=0, atol=1e-12)
    assert np.all(result.evaluation.lengths[:, 0] <= L0 + 1e-9) and np.all(result.evaluation.tensions[:, 0] < 0)

    bare = A * np.max(np.abs(np.cos(theta)))
    grid_peak, grid_design = grid_search(theta)
    ours = result.metrics()["joints"][0]["peak_after"]
    reduction, grid_reduction = bare - ours, bare - grid_peak
    print(
        f"[gas spring] optimiser: F0 {design[0]:.3f} N, k {design[1]:.2f} N/m, b {design[2]:.4f} m, "
        f"peak {ours:.5f} N·m (reduction {reduction:.4f} N·m)"
    )
    print(
        f"[gas spring] grid:      F0 {grid_design['preload']:.3f} N, k {grid_design['stiffness']:.2f} N/m, "
        f"b {grid_design['b']:.4f} m, peak {grid_peak:.5f} N·m (reduction {grid_reduction:.4f} N·m)"
    )
    assert reduction == pytest.approx(grid_reduction, rel=0.01)
    assert ours <= grid_peak * (1 + 1e-6)  # a continuous optimum is at least as good as the grid
    assert grid_design["stiffness"] > 0 and BOUNDS["b"][0] < grid_design["b"] < BOUNDS["b"][1]  # interior
