"""Published cases of docs/reference_cases.md: the project's figures beside the published ones.

Each case is built through the public API, as in the tests (tests/test_reference_*.py assert
the tolerances); this script only prints. Run: .venv/bin/python benchmarks/bench_reference_cases.py
"""

import time
from pathlib import Path

import numpy as np

import springbalance as sb

URDF = Path(__file__).resolve().parents[1] / "urdf"


def row(case, quantity, ours, published, unit):
    print(f"{case:<5s} {quantity:<22s} {ours:>12.6g}   published {published:<10g} {unit}")


clock = time.perf_counter()

# R1: Arakelian & Ghazaryan 2007, rotating link, phi in [2π/3, π]
r1 = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
r1_samples = sb.Workspace.grid(r1, 241, ranges={"pivot": (2 * np.pi / 3, np.pi)})
ground, link = sb.Anchor("universe", (0, 0, 0.16)), sb.Anchor("link1", (0, 0, 0.3))
r1a = sb.solve(
    sb.DesignProblem(r1, r1_samples, [sb.ZeroFreeLengthSpring(ground, link, stiffness=sb.Free(0, 2000))]), starts=2
)
row("R1a", "k [N/m]", r1a.variables["s1.stiffness"], 299, "N/m")
row("R1a", "peak residual", r1a.metrics()["objectives"]["peak"]["after"], 0, "N·m")
coil = sb.CoilMass(coil_diameter=0.04, active_coils=80, wire_length=10.38, shear_modulus=81e9, density=7800.0)
r1b = sb.solve(
    sb.DesignProblem(r1, r1_samples, [sb.ZeroFreeLengthSpring(ground, link, stiffness=sb.Free(1, 2000), mass=coil)]),
    starts=2,
)
row("R1b", "k [N/m]", r1b.spring("s1")["stiffness"], 324.5, "N/m")
row("R1b", "spring mass", r1b.spring("s1")["mass"], 0.8, "kg")
row("R1b", "peak residual", r1b.metrics()["objectives"]["peak"]["after"], 0, "N·m")
r1c_spring = sb.ExtensionSpring(ground, link, stiffness=sb.Free(0, 3000), free_length=0.3, initial_tension=0)
r1c = sb.solve(sb.DesignProblem(r1, r1_samples, [r1c_spring], objective="rms"), starts=2)
row("R1c", "k [N/m]", r1c.variables["s1.stiffness"], 990, "N/m (998 at fine sampling)")
row("R1c", "peak residual", r1c.metrics()["objectives"]["peak"]["after"], 1.81, "N·m (1.72 at fine sampling)")

# R2: Veer 2013, single link over the full turn, g = 9.8
r2 = sb.Mechanism.from_urdf(URDF / "single_link_r2.urdf", gravity=9.8)
r2_samples = sb.Workspace.grid(r2, 721)
ground, link = sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.2, 0, 0))
r2a = sb.solve(
    sb.DesignProblem(r2, r2_samples, [sb.ZeroFreeLengthSpring(ground, link, stiffness=sb.Free(0, 1000))]), starts=2
)
row("R2a", "unbalanced peak", r2a.metrics()["objectives"]["peak"]["before"], 2.45, "N·m")
row("R2a", "K [N/m]", r2a.variables["s1.stiffness"], 122.5, "N/m")
for case, objective, k_published, peak_published in (
    ("R2b", "pe_variance", 161.34, 0.26),
    ("R2c", "peak", 167.26, 0.2278),
):
    spring = sb.ExtensionSpring(ground, link, stiffness=sb.Free(0, 1000), free_length=sb.Free(0.05, 0.5))
    result = sb.solve(sb.DesignProblem(r2, r2_samples, [spring], objective=objective), starts=3)
    row(case, "K [N/m]", result.variables["s1.stiffness"], k_published, "N/m")
    row(case, "l0 [m]", result.variables["s1.free_length"], 0.05, "m")
    row(case, "peak residual", result.metrics()["objectives"]["peak"]["after"], peak_published, "N·m")

# R3: Quaglia & Yin 2015, link 1 carrying the parallelogram load, theta1 in (-90°, 90°), g = 9.8
r3 = sb.Mechanism.from_urdf(URDF / "quaglia_yin_r3.urdf", gravity=9.8)
theta = np.linspace(-np.pi / 2, np.pi / 2, 363)[1:-1]
r3_samples = sb.Workspace.from_array(r3, theta[:, None])
c1max, b1 = (100 * 0.6 + 40 * 1.2) * 9.8, 0.2


def pivot(r5, alpha):
    return sb.Anchor("universe", (r5 * np.cos(np.deg2rad(alpha)), 0, r5 * np.sin(np.deg2rad(alpha))))


arm = sb.Anchor("link1", (b1, 0, 0))
r3a = sb.solve(
    sb.DesignProblem(r3, r3_samples, [sb.ZeroFreeLengthSpring(pivot(6 * b1, 90), arm, stiffness=sb.Free(0, 10000))]),
    starts=2,
)
row("R3a", "k [N/m]", r3a.variables["s1.stiffness"], 4410, "N/m")
row("R3a", "peak error / C1max", r3a.metrics()["objectives"]["peak"]["after"] / c1max, 0, "")
scan = []
for alpha in np.arange(80.0, 92.01, 0.5):
    spring = sb.ConstantForceSpring(pivot(6 * b1, alpha), arm, force=sb.Free(0, 20000))
    result = sb.solve(sb.DesignProblem(r3, r3_samples, [spring]), starts=1)
    scan.append((result.metrics()["objectives"]["rms"]["after"], alpha, result))
_, alpha, best = min(scan, key=lambda item: item[0])
row("R3b", "pivot angle alpha5", alpha, 86, "deg")
row("R3b", "mean |error| / C1max", 100 * np.mean(np.abs(best.residual_torque())) / c1max, 2.8, "%")

# R4: Franchetti, Boschetti & Lenzo 2021, slider anchor per payload
r4 = sb.Mechanism.from_urdf(URDF / "self_regulating_link.urdf", gravity=9.81)
r4_samples = sb.Workspace.grid(r4, 145)
spring = sb.ZeroFreeLengthSpring(
    sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", sb.Segment((0, 0, 0), (0.35, 0, 0))), stiffness=981.0
)
scenarios = [sb.Scenario("bare"), sb.Scenario("1 kg at 0.35 m", [sb.Payload("link1", 1.0, (0.35, 0, 0))])]
r4_result = sb.solve(sb.DesignProblem(r4, r4_samples, [spring], scenarios=scenarios, per_scenario=["s1.b"]), starts=1)
b = [record.spring("s1")["b"]["point"][0] for record in r4_result.scenario_results()]
row("R4", "b bare [m]", b[0], 0.06, "m")
row("R4", "b with 1 kg [m]", b[1], 0.095, "m")
row("R4", "Δb [mm]", 1e3 * (b[1] - b[0]), 35, "mm")

print(f"\n({time.perf_counter() - clock:.1f} s)")
