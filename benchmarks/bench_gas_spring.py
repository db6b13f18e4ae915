"""Gas spring on a single link: the optimiser against a brute-force grid over (F0, k, anchor).

The link of urdf/single_link_r2.urdf (m = 1 kg, centre of mass at 0.25 m, g = 9.8) over
theta ∈ [0°, 60°]; a gas spring pushes from the ground point (0.05, 0, -0.05) m to a point
0.05–0.3 m along the link, extended length l0 = 0.3 m, preload F0 ∈ [0, 100] N, progression
k ∈ [0, 1000] N/m. The grid evaluates the closed-form holding torque
``m g c cos θ - (F0 + k (l0 - L)) dL/dθ`` on 41³ points, then twice on finer 41³ grids
around the best one (tests/springs/test_gas_spring.py asserts the two reductions agree to 1 %).

    python benchmarks/bench_gas_spring.py
"""

import time
from pathlib import Path

import numpy as np

import springbalance as sb

URDF = Path(__file__).resolve().parents[1] / "urdf" / "single_link_r2.urdf"
A, GROUND, L0 = 1.0 * 9.8 * 0.25, np.array([0.05, -0.05]), 0.3
BOUNDS = [(0.0, 100.0), (0.0, 1000.0), (0.05, 0.3)]  # F0 [N], k [N/m], b [m]

mechanism = sb.Mechanism.from_urdf(URDF, gravity=9.8)
workspace = sb.Workspace.grid(mechanism, 121, ranges={"theta": (0, 60)}, degrees=True)
theta = workspace.joint_values[:, 0]

clock = time.perf_counter()
gas = sb.GasSpring(
    sb.Anchor("universe", (GROUND[0], 0, GROUND[1])),
    sb.Anchor("link1", sb.Segment((0.05, 0, 0), (0.3, 0, 0))),
    stiffness=sb.Free(*BOUNDS[1]),
    preload=sb.Free(*BOUNDS[0]),
    free_length=L0,
)
result = sb.solve(sb.DesignProblem(mechanism, workspace, [gas], objective="peak"), starts=8)
optimiser_seconds = time.perf_counter() - clock
values = result.spring("s1")
peak = result.metrics()["joints"][0]["peak_after"]


def peaks(preload, stiffness, b):
    preload, stiffness, b = preload[..., None], stiffness[..., None], b[..., None]
    px, pz = b * np.cos(theta), b * np.sin(theta)
    dx, dz = px - GROUND[0], pz - GROUND[1]
    length = np.hypot(dx, dz)
    tau = A * np.cos(theta) - (preload + stiffness * (L0 - length)) * (dx * -pz + dz * px) / length
    return np.where(np.all(length <= L0, axis=-1), np.max(np.abs(tau), axis=-1), np.inf)


clock = time.perf_counter()
centre, width = None, None
for stage in range(3):
    axes = [
        np.linspace(*(bounds if stage == 0 else (max(bounds[0], c - w), min(bounds[1], c + w))), 41)
        for bounds, c, w in zip(BOUNDS, centre or [0] * 3, width or [0] * 3)
    ]
    grids = np.meshgrid(*axes, indexing="ij")
    table = peaks(*grids)
    best = np.unravel_index(np.argmin(table), table.shape)
    centre, width = [grid[best] for grid in grids], [2 * (axis[1] - axis[0]) for axis in axes]
grid_seconds = time.perf_counter() - clock
grid_peak = float(table[best])
bare = A * np.max(np.abs(np.cos(theta)))

print(f"unbalanced peak {bare:.4f} N·m")
print(f"{'':<11s}{'F0 [N]':>9s}{'k [N/m]':>10s}{'b [m]':>9s}{'peak [N·m]':>12s}{'reduction':>11s}{'time [s]':>10s}")
print(
    f"{'optimiser':<11s}{values['preload']:9.3f}{values['stiffness']:10.2f}{values['b']['point'][0]:9.4f}"
    f"{peak:12.5f}{bare - peak:11.4f}{optimiser_seconds:10.2f}"
)
print(
    f"{'grid':<11s}{centre[0]:9.3f}{centre[1]:10.2f}{centre[2]:9.4f}{grid_peak:12.5f}{bare - grid_peak:11.4f}"
    f"{grid_seconds:10.2f}"
)
print(f"reductions differ by {100 * abs((bare - peak) - (bare - grid_peak)) / (bare - grid_peak):.3f} %")
