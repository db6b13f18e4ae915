"""The clearance fit's distance check on the UR5: one capsule per spring and pose, built two ways in one process.

The fit to the arm (springbalance.design.clearance_fit) measures every spring's distance to every link at
its check poses, again at each round, and at 4× as many when those are clear: it builds a coal capsule per
spring, scenario and pose, hundreds of thousands of times in a UR5 design. ``collision.capsule`` computes
the placement's columns (a helper axis and two cross products) on Python floats; the baseline, run in the
same process on the same poses, is the NumPy builder it replaced (the same columns from small arrays).

Problem: the four springs of bench_clearance.py (UR5, shoulder → upper arm ×2, shoulder → forearm, upper
arm → forearm; anchors in ±0.3 m boxes), at the boxes' centres and at 8 random designs (seed 0). Each
builder measures the design at the check poses (--poses, 512; the fit's pose set 0) --repeat times; the
script prints the time per pass of each, their ratio, and the largest difference of the distances they
give [m]: the two placements are equal bit for bit, so it must be 0.

Run: .venv/bin/python benchmarks/bench_distance_check.py [--poses 512] [--repeat 3]   (make bench-distance-check)
"""

import argparse
import time

import numpy as np

import springbalance as sb
from springbalance.design import clearance_fit
from springbalance.model import collision

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--poses", type=int, default=512)
parser.add_argument("--repeat", type=int, default=3)
args = parser.parse_args()

PAIRS = [
    ("shoulder_link", "upper_arm_link"),
    ("shoulder_link", "forearm_link"),
    ("upper_arm_link", "forearm_link"),
    ("shoulder_link", "upper_arm_link"),
]


def numpy_capsule(start, end, radius):
    """The baseline: the builder ``collision.capsule`` had before (rotation columns from NumPy)."""
    import coal

    axis = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    length = float(np.linalg.norm(axis))
    centre = (np.asarray(start, dtype=float) + np.asarray(end, dtype=float)) / 2
    if length < 1e-12:
        return coal.Sphere(radius), coal.Transform3s(np.eye(3), centre)
    z = axis / length
    helper = np.eye(3)[int(np.argmin(np.abs(z)))]
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return coal.Capsule(radius, length), coal.Transform3s(np.column_stack([x, np.cross(z, x), z]), centre)


mechanism = sb.Mechanism.from_robot("ur5")
RANGES = {"shoulder_lift_joint": [-3.141592653589793, 0.0], "elbow_joint": [-2.6, 2.6]}
springs = [
    sb.ExtensionSpring(
        sb.Anchor(a, sb.Free([-0.3] * 3, [0.3] * 3)),
        sb.Anchor(b, sb.Free([-0.3] * 3, [0.3] * 3)),
        f"s{i + 1}",
        stiffness=sb.Free(0, 5000),
        free_length=sb.Free(0.05, 1.0),
    )
    for i, (a, b) in enumerate(PAIRS)
]
problem = sb.DesignProblem(
    mechanism,
    sb.Workspace.sobol(mechanism, 64, seed=1, ranges=RANGES),
    springs,
    clearance=sb.Clearance(margin=0.005, check_samples=args.poses),
)
checker = clearance_fit._Checker(problem, problem.clearance)
lower, upper = (np.asarray(bound, dtype=float) for bound in problem.variables.bounds())
rng = np.random.default_rng(0)
designs = [np.asarray(problem.variables.start, dtype=float)] + [
    lower + (upper - lower) * rng.random(lower.size) for _ in range(8)
]
capsules = len(checker.pose_sets[0]) * len(checker.springs) * problem.model.n_scenarios * len(designs)


def measured(builder):
    """Seconds of one pass over the designs (best of --repeat) and the distances of the last pass."""
    clearance_fit.capsule = builder
    best, distances = np.inf, []
    for _ in range(args.repeat):
        clock = time.perf_counter()
        distances = [sorted(checker.measure(x, 0)[1].items()) for x in designs]
        best = min(best, time.perf_counter() - clock)
    return best, distances


# alternate the two builders so that the machine's load falls on both alike
new_seconds, new_distances = measured(collision.capsule)
old_seconds, old_distances = measured(numpy_capsule)
new_again, _ = measured(collision.capsule)
new_seconds = min(new_seconds, new_again)
clearance_fit.capsule = collision.capsule

difference = max(abs(a[1] - b[1]) for new, old in zip(new_distances, old_distances) for a, b in zip(new, old))
print(
    f"UR5, {len(checker.springs)} springs, {len(checker.pose_sets[0])} check poses, {len(designs)} designs: "
    f"{capsules} capsules per pass (best of {args.repeat} passes)"
)
print(
    f"  Python floats (collision.capsule):  {new_seconds:6.2f} s, {new_seconds / capsules * 1e6:5.1f} µs per spring and pose"
)
print(
    f"  NumPy columns (baseline):           {old_seconds:6.2f} s, {old_seconds / capsules * 1e6:5.1f} µs per spring and pose"
)
print(
    f"  ratio baseline / now: ×{old_seconds / new_seconds:.2f}; largest difference of the closest distances: {difference:.2e} m"
)
