"""Both cores: 8 starts on a pool of worker processes against the same 8 starts one after another.

Problem: the multi-start of bench_ur5.py part 2 (UR5, 4 extension springs with L ≥ l0, anchors in
±0.3 m boxes, 4,096 Sobol samples, rms objective, 8 starts, seed 0, screening then polish). The
compiled residual is built (or loaded from the disk cache) before the timed runs. Both runs are
made in this process, alternately (--repeats pairs); the figures are their wall and CPU times, the
ratio pool/sequential (goal ≤ 0.6 on 2 cores) and whether the two designs are bit for bit equal.

Run: .venv/bin/python benchmarks/bench_workers.py [--samples 4096] [--starts 8] [--workers W] [--repeats 1]
(make bench-workers; about a minute on 2 cores)
"""

import argparse
import os
import resource
import time

import numpy as np

import springbalance as sb
from springbalance.design.solvers import solve_problem
from springbalance.design.solvers.multistart import _MultiStartSolver

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=4096)
parser.add_argument("--starts", type=int, default=8)
parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
parser.add_argument("--repeats", type=int, default=1)
args = parser.parse_args()

box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)  # noqa: E731
pairs = [
    ("universe", "upper_arm_link"),
    ("universe", "forearm_link"),
    ("upper_arm_link", "forearm_link"),
    ("shoulder_link", "forearm_link"),
]
springs = [
    sb.ExtensionSpring(
        sb.Anchor(a, box()),
        sb.Anchor(b, box()),
        f"s{i + 1}",
        stiffness=sb.Free(0, 5000),
        free_length=sb.Free(0.05, 1.0),
        keep_tension=True,
    )
    for i, (a, b) in enumerate(pairs)
]
mechanism = sb.Mechanism.from_robot("ur5")
problem = sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, args.samples, seed=1), springs)
_MultiStartSolver(problem, "auto", 100, 1e-8).prepare()  # compile (or load from the cache) before timing
print(
    f"UR5, 4 springs, {problem.workspace.size} samples, {problem.variables.size} variables, {args.starts} starts; "
    f"{os.cpu_count()} cores, pool of {args.workers} workers"
)


def cpu_seconds() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def timed(workers):
    wall, cpu = time.perf_counter(), cpu_seconds()
    solution = solve_problem(problem, starts=args.starts, seed=0, progress=False, workers=workers)
    return solution, time.perf_counter() - wall, cpu_seconds() - cpu


rows = []
for _ in range(args.repeats):
    sequential, sequential_wall, sequential_cpu = timed(1)
    pooled, pooled_wall, pooled_cpu = timed(args.workers)
    identical = np.array_equal(sequential.x, pooled.x) and all(
        np.array_equal(a.x, b.x) and a.objective == b.objective and a.status == b.status
        for a, b in zip(sequential.starts, pooled.starts)
    )
    rows.append((sequential_wall, pooled_wall))
    print(
        f"{args.starts} starts one after another: {sequential_wall:6.2f} s wall, {sequential_cpu:6.2f} s CPU "
        f"(CPU/wall {sequential_cpu / sequential_wall:.2f})"
    )
    print(
        f"{args.starts} starts on {args.workers} workers    : {pooled_wall:6.2f} s wall, {pooled_cpu:6.2f} s CPU "
        f"(CPU/wall {pooled_cpu / pooled_wall:.2f})"
    )
    print(
        f"pool / sequential wall time: {pooled_wall / sequential_wall:.2f} (goal ≤ 0.6); designs bit-identical: "
        f"{identical}; best rms {problem.objective_value(problem.evaluate(pooled.x)):.6f} N·m"
    )
if len(rows) > 1:
    ratios = [pool / one for one, pool in rows]
    print(f"ratio over {len(rows)} pairs: median {np.median(ratios):.2f}, best {min(ratios):.2f}")
