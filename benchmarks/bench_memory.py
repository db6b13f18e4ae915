"""No full Jacobian: peak memory per sample and time per start, blocks of samples against one block of all.

Problem: UR5 with the 4 extension springs of bench_ur5.py (anchors in ±0.3 m boxes, stiffness and free
length free, no tension constraint), rms objective, one start (the problem's first guess) with a
budget of --iterations, at each --samples size. Each run is a fresh process; its figures are:
  - peak RSS above the baseline of `import springbalance` and the loaded arm, per sample [KiB]
    (goal ≤ 4 KiB per sample at 100,000 samples);
  - seconds per start (goal ≤ 5 s at 100,000 samples on an idle 2-core machine);
  - the same with one block of all samples (the full Jacobian materialised, as before), in the same run.

Run: .venv/bin/python benchmarks/bench_memory.py [--samples 25000 100000] [--iterations 100] [--skip-full]
(make bench-memory; about 3 minutes on 2 cores)
"""

import argparse
import json
import os
import subprocess
import sys
import textwrap

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, nargs="+", default=[25000, 100000])
parser.add_argument("--iterations", type=int, default=100)
parser.add_argument("--skip-full", action="store_true", help="leave out the runs with one block of all samples")
args = parser.parse_args()

RUN = textwrap.dedent("""
    import json, resource, sys, time
    import springbalance as sb
    from springbalance.design import solvers
    from springbalance.design.solvers import multistart, residuals
    samples, iterations, full = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3] == "full"
    mechanism = sb.Mechanism.from_robot("ur5")
    baseline = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss   # KiB (Linux)
    box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)
    pairs = [("universe", "upper_arm_link"), ("universe", "forearm_link"),
             ("upper_arm_link", "forearm_link"), ("shoulder_link", "forearm_link")]
    springs = [sb.ExtensionSpring(sb.Anchor(a, box()), sb.Anchor(b, box()), f"s{i + 1}", stiffness=sb.Free(0, 5000),
                                  free_length=sb.Free(0.05, 1.0), keep_tension=False)
               for i, (a, b) in enumerate(pairs)]
    problem = sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, samples, seed=1), springs)
    if full:
        problem.least_squares_cache = residuals._LeastSquaresResiduals(problem, block=samples)
    solver = multistart._MultiStartSolver(problem, "least_squares", iterations, 1e-8)
    solver.prepare()
    start = solvers.start_points(problem, 1, 0)[0]
    clock = time.perf_counter()
    from threadpoolctl import threadpool_limits
    with threadpool_limits(limits=1, user_api="blas"):
        record = solver.run(0, start)
    seconds = time.perf_counter() - clock
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"kib_per_sample": (peak - baseline) / samples, "seconds": seconds, "peak_mib": peak / 1024,
                      "baseline_mib": baseline / 1024, "iterations": record.iterations, "rms": record.objective,
                      "block": problem.least_squares_cache.evaluator.block}))
""")


def measure(samples, mode):
    done = subprocess.run(
        [sys.executable, "-c", RUN, str(samples), str(args.iterations), mode],
        capture_output=True,
        text=True,
        env=os.environ,
    )
    if done.returncode != 0:
        sys.exit(done.stderr)
    return json.loads(done.stdout.strip().splitlines()[-1])


print(f"UR5, 4 springs, 32 variables, one start of at most {args.iterations} iterations")
for samples in args.samples:
    for mode in ("blocks",) + (() if args.skip_full else ("full",)):
        figures = measure(samples, mode)
        label = f"blocks of {figures['block']} samples" if mode == "blocks" else "one block (full Jacobian)"
        print(
            f"{samples:>7} samples, {label:<26}: {figures['kib_per_sample']:5.2f} KiB/sample above the import "
            f"baseline (peak {figures['peak_mib']:.0f} MiB, baseline {figures['baseline_mib']:.0f} MiB), "
            f"{figures['seconds']:6.2f} s per start ({figures['iterations']} iterations, "
            f"{1e6 * figures['seconds'] / (samples * max(figures['iterations'], 1)):.2f} µs/sample/iteration), "
            f"rms {figures['rms']:.6f}",
            flush=True,
        )
