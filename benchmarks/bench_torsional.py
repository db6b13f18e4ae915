"""Torsional spring on a single link: peak-torque optimum vs pe_variance optimum.

The link of urdf/single_link_r2.urdf (Veer 2013: m = 1 kg, centre of mass at 0.25 m,
g = 9.8, unbalanced peak 2.45 N·m) carries a torsional spring on its joint, rate
k ∈ [0, 20] N·m/rad and neutral angle theta0 ∈ [-2π, 2π] free. For each workspace the
script prints both optima and the peak and RMS torque each leaves. Minimising the
potential-energy variance is not minimising the peak: on the full turn it even raises the
peak above the unbalanced link's (tests/springs/test_torsional.py asserts the ordering).

    python benchmarks/bench_torsional.py
"""

import time
from pathlib import Path

import numpy as np

import springbalance as sb

URDF = Path(__file__).resolve().parents[1] / "urdf" / "single_link_r2.urdf"
mechanism = sb.Mechanism.from_urdf(URDF, gravity=9.8)

print(
    f"{'workspace':<16s}{'objective':<13s}{'k [N·m/rad]':>12s}{'theta0 [°]':>12s}{'peak [N·m]':>12s}"
    f"{'rms [N·m]':>11s}{'time [s]':>10s}"
)
for label, (lower, upper) in (("0° … 180°", (0, 180)), ("-45° … 135°", (-45, 135)), ("full turn", (-180, 180))):
    workspace = sb.Workspace.grid(mechanism, 361, ranges={"theta": (lower, upper)}, degrees=True)
    bare = workspace.kinematics().gravity_torque[:, 0]
    print(
        f"{label:<16s}{'(no spring)':<13s}{'':>12s}{'':>12s}{np.max(np.abs(bare)):12.4f}"
        f"{np.sqrt(np.mean(bare**2)):11.4f}"
    )
    for objective in ("peak", "pe_variance"):
        spring = sb.TorsionalSpring("theta", stiffness=sb.Free(0, 20), neutral_angle=sb.Free(-2 * np.pi, 2 * np.pi))
        clock = time.perf_counter()
        result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring], objective=objective), starts=4)
        seconds = time.perf_counter() - clock
        row = result.metrics()["joints"][0]
        values = result.spring("s1")
        print(
            f"{'':<16s}{objective:<13s}{values['stiffness']:12.4f}{np.degrees(values['neutral_angle']):12.2f}"
            f"{row['peak_after']:12.4f}{row['rms_after']:11.4f}{seconds:10.2f}"
        )
