"""UR5 with four springs kept clear of its own links (the URDF's collision meshes), beside the same design without.

Problem: four ideal extension springs, shoulder→upper arm, shoulder→forearm, upper arm→forearm and a
second shoulder→upper arm (every anchor free in a ±0.3 m box of its body; stiffness in [0, 5000] N/m, free
length in [0.05, 1] m). bench_ur5.py anchors two springs on the ground instead: with the shoulder pan's full
turn, the line from any ground point off the pan axis to the upper arm passes through the turning shoulder
column at some pan angle, so no such spring can keep clear (a real balancer is mounted on the shoulder,
which turns with the pan and carries the same gravity torques), rms objective, on a Sobol workspace (seed 1) of the URDF's joint ranges
except two: shoulder lift in [-π, 0] (the upper arm above the base's horizontal plane) and elbow in
[-2.6, 2.6] rad (±149°; beyond it the forearm folds into the upper arm, poses the arm cannot take).
Solved twice by ``DesignProblem.solve`` with the same starts and seed:

  - unconstrained: no clearance;
  - clearance:     ``sb.Clearance(margin=0.005, check_samples=C)``: every spring (a capsule of radius
                   10 mm) keeps 5 mm from every link it is not attached to, enforced by the linearised
                   separating-plane rows of springbalance.design.clearance (meshes as convex hulls).

Both designs are then checked *independently* with the clearance report (coal against the URDF's own
collision meshes, not their hulls) at 10·C Sobol poses (or --verify-samples) (seed 0) of the workspace's joint ranges. The
script prints the time of each solve, the rms reduction of each, the price of clearance, and the smallest
distance of every spring in the dense check; it says loudly when a spring of the clearance design comes
below the margin.

Run: .venv/bin/python benchmarks/bench_clearance.py [--samples 1024] [--check-samples 512] [--starts 4] [--rounds 12]
     [--verify-samples N] [--fit-starts N]
(make bench-clearance; a few minutes on 2 cores)
"""

import argparse
import time

import springbalance as sb

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=1024)
parser.add_argument("--check-samples", type=int, default=512)
parser.add_argument("--starts", type=int, default=4)
parser.add_argument("--seed", type=int, default=0)
parser.add_argument("--margin", type=float, default=0.005)
parser.add_argument("--rounds", type=int, default=12, help="most re-solves of the fitting loop")
parser.add_argument("--fit-starts", type=int, default=1, help="clearance.starts: best designs the loop fits")
parser.add_argument(
    "--verify-samples", type=int, default=None, help="poses of the independent check (default 10 × --check-samples)"
)
args = parser.parse_args()
VERIFY = args.verify_samples or 10 * args.check_samples

PAIRS = [
    ("shoulder_link", "upper_arm_link"),
    ("shoulder_link", "forearm_link"),
    ("upper_arm_link", "forearm_link"),
    ("shoulder_link", "upper_arm_link"),
]


def springs():
    def box():
        return sb.Free([-0.3] * 3, [0.3] * 3)

    return [
        sb.ExtensionSpring(
            sb.Anchor(a, box()),
            sb.Anchor(b, box()),
            f"s{i + 1}",
            stiffness=sb.Free(0, 5000),
            free_length=sb.Free(0.05, 1.0),
        )
        for i, (a, b) in enumerate(PAIRS)
    ]


mechanism = sb.Mechanism.from_robot("ur5")
RANGES = {"shoulder_lift_joint": [-3.141592653589793, 0.0], "elbow_joint": [-2.6, 2.6]}
workspace = sb.Workspace.sobol(mechanism, args.samples, seed=1, ranges=RANGES)
print(
    f"UR5, 4 extension springs, {args.samples} Sobol samples, {args.starts} starts, seed {args.seed}; "
    f"clearance margin {args.margin * 1e3:g} mm checked on {args.check_samples} poses while fitting, "
    f"independent check on {VERIFY} poses (URDF meshes)\n"
)

results = {}
for label, clearance in (
    ("unconstrained", None),
    (
        "clearance",
        sb.Clearance(margin=args.margin, check_samples=args.check_samples, rounds=args.rounds, starts=args.fit_starts),
    ),
):
    clock = time.perf_counter()
    problem = sb.DesignProblem(mechanism, workspace, springs(), clearance=clearance)
    result = sb.solve(problem, starts=args.starts, seed=args.seed)
    seconds = time.perf_counter() - clock
    rms = result.metrics()["objectives"]["rms"]
    check = result.clearance(samples=VERIFY, margin=args.margin)
    results[label] = (result, seconds, rms, check)
    print(
        f"{label:>13}: {seconds:7.1f} s, rms {rms['before']:.4g} → {rms['after']:.4g} N·m "
        f"({rms['reduction_percent']:.2f} % reduction)"
    )
    if result.fit is not None:
        fit = result.fit
        print(
            f"{'':>15}fit: {fit.rounds} round(s), {fit.rows} rows, {fit.seconds:.1f} s, "
            f"{'converged' if fit.converged else 'NOT CONVERGED'}"
        )
    for row in check.rows:
        flag = (
            ""
            if row.distance >= args.margin
            else (
                "   <-- BELOW THE MARGIN"
                if label == "clearance"
                else "   (overlap)"
                if row.distance < 0
                else "   (below margin)"
            )
        )
        print(
            f"{'':>15}{row.spring}: closest {row.distance * 1e3:8.1f} mm to {row.link} "
            f"(radius {row.radius * 1e3:.0f} mm){flag}"
        )
    print()

free, fitted = results["unconstrained"], results["clearance"]
print(
    f"price of clearance: rms reduction {free[2]['reduction_percent']:.2f} % → {fitted[2]['reduction_percent']:.2f} % "
    f"({fitted[2]['reduction_percent'] - free[2]['reduction_percent']:+.2f} points); "
    f"time ×{fitted[1] / free[1]:.1f} ({free[1]:.1f} s → {fitted[1]:.1f} s)"
)
print(
    f"independent check of the clearance design on {fitted[3].poses} poses: "
    f"{'CLEAR (no spring below the margin)' if fitted[3].clear else 'NOT CLEAR'}"
)
