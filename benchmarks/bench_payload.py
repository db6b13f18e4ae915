"""Two-link arm carrying 0–2 kg at the tip: adjustable sliders vs one robust design vs a design for 0 kg.

urdf/two_link_planar.urdf (link1 2 kg, link2 1 kg, tool 0.5 kg at the tip; g = 9.81), a 9×9 grid of
shoulder ∈ [-90°, 90°], elbow ∈ [-120°, 120°], payload 0, 1 or 2 kg at the tool (body ``tool``).
Two zero-free-length springs: ground → link1 and ground → link2, ground anchors in boxes, link
anchors on segments along the links (sliders), stiffness ∈ [0, 5000] N/m, objective peak.

- tuned for 0 kg: one design for the bare arm;
- robust: one fixed design, worst case over the three payloads;
- slider: springs (stiffness, ground anchors) shared, link anchors per payload.

The script prints each design's peak residual torque at each payload and the worst case.
tests/design/test_scenarios.py asserts the orderings slider < robust < tuned-for-0-kg at 2 kg.

    python benchmarks/bench_payload.py
"""

import time
from pathlib import Path

import numpy as np

import springbalance as sb

URDF = Path(__file__).resolve().parents[1] / "urdf" / "two_link_planar.urdf"
MASSES = [0.0, 1.0, 2.0]


def springs():
    return [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([-0.1, 0, 0.02], [0.1, 0, 0.3])),
            sb.Anchor("link1", sb.Segment([0.02, 0, 0], [0.5, 0, 0])),
            stiffness=sb.Free(0, 5000),
            name="shoulder_spring",
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([-0.3, 0, -0.1], [0.3, 0, 0.6])),
            sb.Anchor("link2", sb.Segment([0.02, 0, 0], [0.4, 0, 0])),
            stiffness=sb.Free(0, 5000),
            name="elbow_spring",
        ),
    ]


mechanism = sb.Mechanism.from_urdf(URDF)
workspace = sb.Workspace.grid(
    mechanism, {"shoulder": 9, "elbow": 9}, ranges={"shoulder": (-90, 90), "elbow": (-120, 120)}, degrees=True
)
payloads = sb.payload_scenarios("tool", MASSES)
stacked = sb.DesignProblem(mechanism, workspace, springs(), scenarios=payloads).workspace  # N samples per payload
bare_peaks = [float(np.max(np.abs(block))) for block in np.split(stacked.kinematics().gravity_torque, len(MASSES))]

problems = {
    "tuned for 0 kg": sb.DesignProblem(mechanism, workspace, springs(), objective="peak"),
    "robust (fixed)": sb.DesignProblem(mechanism, workspace, springs(), objective="peak", scenarios=payloads),
    "slider per payload": sb.DesignProblem(
        mechanism,
        workspace,
        springs(),
        objective="peak",
        scenarios=payloads,
        per_scenario=["shoulder_spring.b", "elbow_spring.b"],
    ),
}
print(
    f"{'design':<22s}" + "".join(f"{f'peak @ {m:g} kg':>14s}" for m in MASSES) + f"{'worst case':>12s}{'time [s]':>10s}"
)
print(f"{'(no springs)':<22s}" + "".join(f"{p:14.4f}" for p in bare_peaks) + f"{max(bare_peaks):12.4f}")
results = {}
for label, problem in problems.items():
    clock = time.perf_counter()
    result = sb.solve(problem, starts=4)
    seconds = time.perf_counter() - clock
    if problem.per_scenario:
        peaks = np.array([row["peak"] for row in problem.scenario_table(result.x)])
    else:
        peaks = sb.residual_vs_payload(result, "tool", MASSES).peak
    results[label] = result
    print(f"{label:<22s}" + "".join(f"{p:14.4f}" for p in peaks) + f"{max(peaks):12.4f}{seconds:10.2f}")

slider = problems["slider per payload"]
print("\nslider positions along the links [m] and the shared springs")
for row, scenario in zip(slider.scenario_table(results["slider per payload"].x), payloads):
    shoulder, elbow = row["variables"]["shoulder_spring.b.s"], row["variables"]["elbow_spring.b.s"]
    print(
        f"  {scenario.name:>6s}: link1 anchor at {0.02 + 0.48 * shoulder:.4f} m, link2 anchor at {0.02 + 0.38 * elbow:.4f} m"
    )
values = results["slider per payload"].variables
print(
    f"  stiffness: shoulder_spring {values['shoulder_spring.stiffness']:.1f} N/m, "
    f"elbow_spring {values['elbow_spring.stiffness']:.1f} N/m"
)
