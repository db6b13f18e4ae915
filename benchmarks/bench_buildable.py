"""UR5 with four buildable helical extension springs against four ideal extension springs: the price of buildability.

Problem (issue "bench_buildable"): UR5 from example-robot-data; 4 springs ground→upper arm, ground→forearm,
upper arm→forearm, shoulder→forearm (the topologies of bench_ur5.py); every anchor free in a ±0.3 m box of
its body; the Sobol workspace of bench_ur5.py (seed 1), 128 samples by default; rms objective.

Why 128 samples and not bench_ur5.py's 4,096: the buildable problem is solved by IPOPT with every coil rule
at every sample, and its time grows with the samples (on the 2-core development machine, 4 starts:
about 470 s at 256 samples, against 2 s for the ideal springs). At 128 the whole script stays within
about 5 minutes. Both designs are then evaluated (not re-optimised) on the 4,096 samples of bench_ur5.py
(the 128 are the first of them): their reductions there, and whether each coil is still buildable at
poses it was not designed on.

  - ideal:     ``sb.ExtensionSpring`` with stiffness in [0, 5000] N/m and free length in [0.05, 1] m
               (default options: ``L ≥ l0`` at every sample, no initial tension);
  - buildable: ``HelicalExtensionSpring`` of music wire, outer diameter at most 60 mm, everything else
               default: wire d, coil D, active coils n and initial tension free, the rules of a buildable
               coil (body and hook stresses, index 4–12, initial-tension band, L ≥ l0) as constraints at
               every sample, a warm start from the ideal twin and the wires rounded to standard sizes.

Both are solved by ``DesignProblem.solve`` with the same number of starts and the same seed; the time is
the wall time of building the problem and solving it (for the buildable springs this includes the twin
solve of the warm start and the standard-wire re-optimisation). The script prints, for each, the time and
the rms and peak reductions over all joints and per joint; for the buildable springs each spring's spec
sheet and the cost of rounding to standard wire; then the price: the difference in rms reduction
(percentage points) and the ratio of the times. A spring whose spec sheet says it is not buildable is
reported loudly (the script does not stop).

Run: .venv/bin/python benchmarks/bench_buildable.py [--samples 128] [--starts 4] [--seed 0]
                                                    [--check-samples 4096]   (0: no check)
(about 2 minutes on 2 cores at the defaults, nearly all of it in the buildable solve)
"""

import argparse
import time

import numpy as np

import springbalance as sb
import springbalance.pipeline.sequence as sequence
from springbalance.design.solvers import FEASIBILITY_TOLERANCE
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=128)
parser.add_argument("--check-samples", type=int, default=4096)
parser.add_argument("--starts", type=int, default=4)
parser.add_argument("--seed", type=int, default=0)
args = parser.parse_args()

PAIRS = [
    ("universe", "upper_arm_link"),
    ("universe", "forearm_link"),
    ("upper_arm_link", "forearm_link"),
    ("shoulder_link", "forearm_link"),
]
MPA = 1e6


def anchors(a, b):
    def box():
        return sb.Free([-0.3] * 3, [0.3] * 3)

    return sb.Anchor(a, box()), sb.Anchor(b, box())


def ideal_springs():
    return [
        sb.ExtensionSpring(*anchors(a, b), f"s{i + 1}", stiffness=sb.Free(0, 5000), free_length=sb.Free(0.05, 1.0))
        for i, (a, b) in enumerate(PAIRS)
    ]


def buildable_springs():
    return [
        HelicalExtensionSpring(*anchors(a, b), f"s{i + 1}", material="music_wire", max_outer_diameter=0.06)
        for i, (a, b) in enumerate(PAIRS)
    ]


# Where the time goes: springbalance.solve runs these steps (springbalance.pipeline.steps); each is timed
# (the wrappers only time)
PHASES = {
    "first_guess": "warm start (ideal twin solve + winding)",
    "multi_start": "multi-start solve",
    "round_wires": "standard-wire rounding",
}
phase_times = {}


def timed(name, function):
    def wrapper(*args, **kwargs):
        clock = time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            phase_times[name] = phase_times.get(name, 0.0) + time.perf_counter() - clock

    return wrapper


sequence.STEPS = tuple(timed(step.__name__, step) if step.__name__ in PHASES else step for step in sequence.STEPS)


def percent(value, width):
    return f"{value:{width}.2f}" if np.isfinite(value) else f"{'—':>{width}s}"


mechanism = sb.Mechanism.from_robot("ur5")
workspace = sb.Workspace.sobol(mechanism, args.samples, seed=1)


def run(label, springs):
    phase_times.clear()
    clock = time.perf_counter()
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="rms")
    result = sb.solve(problem, starts=args.starts, seed=args.seed, progress=False)
    seconds = time.perf_counter() - clock
    metrics = result.metrics()
    rms, peak = metrics["objectives"]["rms"], metrics["objectives"]["peak"]
    start_times = [record.seconds for record in result.starts]
    print(f"\n=== {label}: {problem.variables.size} design variables, {args.starts} starts, seed {args.seed}")
    print(
        f"wall time {seconds:.2f} s (problem build + solve; per start median "
        f"{np.median(start_times) if start_times else float('nan'):.2f} s); method {result.method}; "
        f"status: {result.status}"
    )
    print(
        "  of which " + ", ".join(f"{PHASES[name]} {phase_times[name]:.2f} s" for name in PHASES if name in phase_times)
    )
    print(
        f"all joints: rms {rms['before']:.4f} → {rms['after']:.5f} N·m ({rms['reduction_percent']:.2f} % lower), "
        f"peak {peak['before']:.4f} → {peak['after']:.4f} N·m ({peak['reduction_percent']:.2f} % lower)"
    )
    print(
        f"  {'joint':<24s}{'rms before':>11s}{'rms after':>11s}{'rms Δ%':>9s}{'peak before':>13s}"
        f"{'peak after':>12s}{'peak Δ%':>9s}"
    )
    for row in metrics["joints"]:
        name = f"{row['joint']} [{row['unit']}]"
        print(
            f"  {name:<24s}{row['rms_before']:11.4f}{row['rms_after']:11.5f}{percent(row['rms_reduction_percent'], 9)}"
            f"{row['peak_before']:13.4f}{row['peak_after']:12.4f}{percent(row['peak_reduction_percent'], 9)}"
        )
    if metrics["max_violation"] > FEASIBILITY_TOLERANCE:
        print(
            f"!!! {label}: INFEASIBLE design, largest constraint violation {metrics['max_violation']:.3g} "
            f"(tolerance {FEASIBILITY_TOLERANCE:g})"
        )
    return result, seconds, metrics


ideal, ideal_time, ideal_metrics = run("ideal extension springs", ideal_springs())
print(
    "  springs: "
    + "; ".join(f"{r['name']} k {r['stiffness']:.1f} N/m, l0 {1e3 * r['free_length']:.1f} mm" for r in ideal.springs)
)

buildable, buildable_time, buildable_metrics = run(
    "buildable helical extension springs (music wire, outer diameter ≤ 60 mm)", buildable_springs()
)

not_buildable = []
print("  spec sheets (after rounding to standard wire; stress/allowable: body, hook bending, hook torsion):")
print(
    f"  {'spring':<7s}{'wire d':>9s}{'D':>9s}{'D/d':>6s}{'n':>8s}{'free l0':>10s}{'F_i':>9s}{'k':>11s}"
    f"{'max load':>10s}{'body':>7s}{'hook B':>7s}{'hook T':>7s}{'mass':>9s}  buildable"
)
for record in buildable.springs:
    sheet = record["helical"]
    ratios = (
        sheet["max_stress"] / sheet["allowable_stress"],
        sheet["hook_bending_stress"] / sheet["hook_bending_allowable"],
        sheet["hook_torsion_stress"] / sheet["hook_torsion_allowable"],
    )
    print(
        f"  {record['name']:<7s}{1e3 * sheet['wire_diameter']:6.2f} mm{1e3 * sheet['mean_diameter']:6.2f} mm"
        f"{sheet['index']:6.2f}{sheet['active_coils']:8.2f}{1e3 * sheet['free_length']:7.1f} mm"
        f"{sheet['initial_tension']:7.1f} N{sheet['rate']:7.0f} N/m{sheet['max_load']:8.1f} N"
        f"{ratios[0]:7.3f}{ratios[1]:7.3f}{ratios[2]:7.3f}{sheet['mass']:6.3f} kg  "
        f"{'yes' if sheet['buildable'] else 'NO'}"
    )
    print(
        f"         length {1e3 * sheet['shortest_length']:.1f} … {1e3 * sheet['longest_length']:.1f} mm; body stress "
        f"{sheet['max_stress'] / MPA:.0f} of {sheet['allowable_stress'] / MPA:.0f} MPa allowable"
    )
    if not sheet["buildable"]:
        not_buildable.append(record["name"])
        print(f"  !!! SPRING {record['name']} IS NOT BUILDABLE: " + "; ".join(sheet["reasons"]))

rounding = buildable.wire_rounding
unbalanced_rms = buildable_metrics["objectives"]["rms"]["before"]
if rounding is None:
    print("!!! no standard-wire rounding was done (result.wire_rounding is None)")
else:
    wires = ", ".join(
        f"{name} {1e3 * continuous:.3f} → {1e3 * standard:.2f} mm"
        for name, (continuous, standard) in rounding.wires.items()
    )
    print(f"  standard wire: {wires or 'none rounded'}")
    print(
        f"  rounding cost: rms {rounding.continuous_objective:.5f} → {rounding.objective:.5f} N·m "
        f"({rounding.cost_percent:+.2f} %); rms reduction before rounding "
        f"{100 * (1 - rounding.continuous_objective / unbalanced_rms):.2f} %"
    )
    for name, reason in rounding.unrounded.items():
        print(f"  !!! wire of {name} left continuous: {reason}")

# ---------------------------------------------------------------- both designs on the larger workspace of bench_ur5.py
checks = {}
if args.check_samples:
    check_workspace = sb.Workspace.sobol(mechanism, args.check_samples, seed=1)
    prefix = check_workspace.size >= workspace.size and np.allclose(
        check_workspace.joint_values[: workspace.size], workspace.joint_values
    )
    print(
        f"\n=== both designs evaluated on {check_workspace.size} Sobol samples (seed 1, as bench_ur5.py"
        + (
            f"; the {workspace.size} design samples are the first of them, {check_workspace.size - workspace.size} "
            "are unseen)"
            if prefix
            else ")"
        )
    )
    for label, result in (("ideal", ideal), ("buildable", buildable)):
        check = result.on_workspace(check_workspace)
        objectives = check.metrics()["objectives"]
        checks[label] = objectives
        violation = check.evaluation.max_violation
        print(
            f"{label:<10s}: rms {objectives['rms']['after']:.5f} N·m ({objectives['rms']['reduction_percent']:.2f} % lower), "
            f"peak {objectives['peak']['after']:.4f} N·m ({objectives['peak']['reduction_percent']:.2f} % lower)"
        )
        if violation > FEASIBILITY_TOLERANCE:
            print(f"  !!! {label}: a constraint is violated on these samples, by up to {violation:.3g} (scaled units)")
            for flag in check.warnings():
                if flag.kind == "law":  # a spring that leaves its law (slack, ...); coils: their spec sheets below
                    print(f"    [{flag.kind}] {flag.message}")
        for record in check.springs:
            sheet = record.get("helical")
            if sheet is None:
                continue
            if sheet["buildable"]:
                print(
                    f"  {record['name']}: buildable over these samples too (length {1e3 * sheet['shortest_length']:.1f} … "
                    f"{1e3 * sheet['longest_length']:.1f} mm, body stress/allowable "
                    f"{sheet['max_stress'] / sheet['allowable_stress']:.3f})"
                )
            else:
                print(
                    f"  !!! SPRING {record['name']} IS NOT BUILDABLE over these samples: " + "; ".join(sheet["reasons"])
                )
                not_buildable.append(f"{record['name']} (on {check_workspace.size} samples)")

# ---------------------------------------------------------------- the price of buildability
ideal_rms, built_rms = ideal_metrics["objectives"]["rms"], buildable_metrics["objectives"]["rms"]
ideal_peak, built_peak = ideal_metrics["objectives"]["peak"], buildable_metrics["objectives"]["peak"]
print(f"\n=== price of buildability (UR5, {workspace.size} Sobol samples, {args.starts} starts, seed {args.seed})")
print(
    f"rms reduction : ideal {ideal_rms['reduction_percent']:.2f} %, buildable {built_rms['reduction_percent']:.2f} % "
    f"→ {ideal_rms['reduction_percent'] - built_rms['reduction_percent']:.2f} percentage points "
    f"(residual rms {ideal_rms['after']:.5f} vs {built_rms['after']:.5f} N·m, "
    f"{built_rms['after'] / ideal_rms['after']:.2f}×)"
)
print(
    f"peak reduction: ideal {ideal_peak['reduction_percent']:.2f} %, buildable {built_peak['reduction_percent']:.2f} % "
    f"→ {ideal_peak['reduction_percent'] - built_peak['reduction_percent']:.2f} percentage points"
)
if checks:
    ideal_check, built_check = checks["ideal"]["rms"], checks["buildable"]["rms"]
    print(
        f"  on {args.check_samples} samples: ideal {ideal_check['reduction_percent']:.2f} %, buildable "
        f"{built_check['reduction_percent']:.2f} % → {ideal_check['reduction_percent'] - built_check['reduction_percent']:.2f} "
        f"percentage points"
    )
print(
    f"time          : ideal {ideal_time:.2f} s, buildable {buildable_time:.2f} s → {buildable_time / ideal_time:.1f}×"
)
if not_buildable:
    print(f"!!! NOT BUILDABLE: {', '.join(not_buildable)} (see the spec sheets above)")
else:
    print(
        f"all {len(buildable.springs)} buildable springs pass their spec sheet"
        + (f" (on the {workspace.size} design samples and on the {args.check_samples} check samples)" if checks else "")
    )
