"""The clearance fit's distance check on the UR5, against two baselines run in the same process on the same poses.

The fit to the arm (springbalance.design.clearance_fit) measures every spring's distance to every link at
its check poses, again at each round, at 4× as many when those are clear, and the verification at 10× as many.
Three ways, each over the same designs and poses:

  - now:      ``_Checker.measure``: a lower bound of every pair at every pose from bounding capsules, in one
              pass of array operations (springbalance.design.clearance_distances), coal asked only where the
              bound is within the margin and descent band, and at each pair's least; capsules built on
              Python floats (``collision.capsule``);
  - coal:     coal for every pair at every pose (the check before the bounds), the same capsules;
  - numpy:    the same as coal, with the capsule builder before that (its rotation's columns from NumPy's
              small-array operations): the check as it was at the start of session 37.

Problem: the four springs of bench_clearance.py (UR5, shoulder → upper arm ×2, shoulder → forearm, upper
arm → forearm; anchors in ±0.3 m boxes), at the boxes' centres and at 8 random designs (seed 0), at the check
poses (--poses, 512; the fit's pose set 0), best of --repeat passes. The script prints the time of each, the
ratios, and whether each baseline finds the same contacts below the margin and the same closest distance of
every spring, bit for bit (it must).

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


def every_pair(x):
    """The baseline's measure: coal's distance of every pair at every pose, then the same reductions."""
    radius, pairs = checker._radii(x), list(checker._pairs())
    poses = checker.pose_sets[0]
    distances = np.empty((len(poses), len(pairs)))
    for sample, q in enumerate(poses):
        checker.scene.place(q)
        distances[sample] = checker.placed_distances(pairs, x, radius)
    below = {
        pair + (0, int(s)): float(distances[s, c])
        for c, pair in enumerate(pairs)
        for s in np.flatnonzero(distances[:, c] < 0.005)
    }
    closest = {}
    for c, pair in enumerate(pairs):
        names = (pair[1], pair[2]) if pair[0] == "spring" else (pair[1],)
        for name in names:
            closest[name] = min(closest.get(name, np.inf), float(distances[:, c].min()))
    return below, closest


def measured(how):
    """Seconds of one pass over the designs (best of --repeat) and what the last pass found."""
    best, found = np.inf, []
    for _ in range(args.repeat):
        clock = time.perf_counter()
        found = [how(x) for x in designs]
        best = min(best, time.perf_counter() - clock)
    return best, found


def now(x):
    below, closest, _ = checker.measure(x, 0)
    return below, closest


def with_builder(builder):
    def run(x):
        clearance_fit.capsule = builder
        try:
            return every_pair(x)
        finally:
            clearance_fit.capsule = collision.capsule

    return run


# how many pairs `now` asks coal for, of all the pairs at all the poses
asked = [0]
placed_distances = checker.placed_distances


def counted(pairs, x, radius):
    asked[0] += len(pairs)
    return placed_distances(pairs, x, radius)


checker.placed_distances = counted
for x in designs:
    checker.measure(x, 0)
checker.placed_distances = placed_distances
every = len(designs) * len(checker.pose_sets[0]) * len(list(checker._pairs()))

# alternate so that the machine's load falls on all alike
times = {"now": [], "coal": [], "numpy": []}
results = {}
for _ in range(2):
    for label, how in (("now", now), ("coal", with_builder(collision.capsule)), ("numpy", with_builder(numpy_capsule))):
        seconds, results[label] = measured(how)
        times[label].append(seconds)
best = {label: min(values) for label, values in times.items()}
print(
    f"UR5, {len(checker.springs)} springs, {len(checker.pose_sets[0])} check poses, {len(designs)} designs "
    f"(best of {2 * args.repeat} passes); now asks coal for {asked[0]} of the {every} pairs at all poses "
    f"({100 * asked[0] / every:.1f} %)"
)
for label in ("now", "coal", "numpy"):
    same = all(set(a[0]) == set(b[0]) and a[1] == b[1] for a, b in zip(results[label], results["now"]))
    print(
        f"  {label:>5}: {best[label]:6.2f} s a pass, ×{best[label] / best['now']:.2f} of now; same contacts and closest distances as now: {same}"
    )
