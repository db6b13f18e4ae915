"""UR5 with four extension springs: springbalance's solver against SciPy and CMA-ES.

Problem (issue "core engine", must-hold 3): UR5 from example-robot-data; 4 extension
springs ground→upper arm, ground→forearm, upper arm→forearm, shoulder→forearm; every anchor
free in a ±0.3 m box of its body, stiffness in [0, 5000] N/m, free length in [0.05, 1] m;
4,096 Sobol samples of the URDF joint ranges; rms objective.

Part 1 compares, from the same start points and on the same bounded (unconstrained) problem:
  - springbalance: exact Jacobian of the CasADi per-sample model (JIT-compiled when a C compiler
    is available), start preparation, and SciPy's trust-region reflective method on the
    compressed (n+1-row) residual;
  - SciPy `least_squares` (trf) with 2-point finite differences on the same residuals;
  - CMA-ES (`cma`) on the same scaled variables.
Part 2 runs the default multi-start (with the tension constraint L ≥ l0 of every spring) and
prints the time per start and the per-joint table.

Run: .venv/bin/python benchmarks/bench_ur5.py [--samples 4096] [--starts 8] [--compare-starts 4]
                                              [--baseline-iterations 100] [--cma-evaluations 3000]
(about 4 minutes on 2 cores, most of it in the baselines)
"""

import argparse
import time

import numpy as np
from scipy.optimize import least_squares

import springbalance as sb
from springbalance.design.solvers import _MultiStartSolver, start_points
from threadpoolctl import threadpool_limits

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=4096)
parser.add_argument("--starts", type=int, default=8)
parser.add_argument("--baseline-iterations", type=int, default=100)
parser.add_argument("--compare-starts", type=int, default=4)
parser.add_argument("--cma-evaluations", type=int, default=3000)
args = parser.parse_args()


def springs(keep_tension):
    box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)
    pairs = [("universe", "upper_arm_link"), ("universe", "forearm_link"),
             ("upper_arm_link", "forearm_link"), ("shoulder_link", "forearm_link")]
    return [sb.ExtensionSpring(sb.Anchor(a, box()), sb.Anchor(b, box()), f"s{i + 1}",
                               stiffness=sb.Free(0, 5000), free_length=sb.Free(0.05, 1.0), keep_tension=keep_tension)
            for i, (a, b) in enumerate(pairs)]


mechanism = sb.Mechanism.from_robot("ur5")
workspace = sb.Workspace.sobol(mechanism, args.samples, seed=1)
problem = sb.DesignProblem(mechanism, workspace, springs(keep_tension=False))
print(f"UR5, {workspace.size} Sobol samples, {problem.variables.size} design variables, unbalanced rms "
      f"{problem.torque_scale:.4f} N·m")

# ---------------------------------------------------------------- part 1: same starts, three solvers
starts = start_points(problem, args.compare_starts, seed=0)
solver = _MultiStartSolver(problem, "least_squares", args.baseline_iterations, 1e-8)  # the default tolerance of DesignProblem.solve
clock = time.perf_counter()
solver.run(0, starts[0])  # the first call builds and JIT-compiles the model: timed separately
setup = time.perf_counter() - clock


def residuals(z):  # the same scaled residuals, evaluated numerically (CasADi virtual machine, no JIT)
    evaluation = problem.evaluate(problem.scale(z))
    return (evaluation.tau * problem.weights).reshape(-1) / (problem.torque_scale * np.sqrt(evaluation.tau.size))


import cma  # noqa: E402  (benchmark-only dependency)

rows = []
for index, z0 in enumerate(starts):
    clock = time.perf_counter()
    with threadpool_limits(limits=1, user_api="blas"):  # as DesignProblem.solve runs; the baselines keep the default
        ours = solver.run(index, z0)
    ours_time = time.perf_counter() - clock

    clock = time.perf_counter()
    fd = least_squares(residuals, z0, jac="2-point", bounds=(0.0, 1.0), method="trf", max_nfev=args.baseline_iterations)
    fd_time = time.perf_counter() - clock
    fd_rms = float(np.sqrt(2 * fd.cost)) * problem.torque_scale

    clock = time.perf_counter()
    strategy = cma.CMAEvolutionStrategy(z0, 0.2, {"bounds": [0, 1], "maxfevals": args.cma_evaluations,
                                                  "verbose": -9, "seed": 1})
    strategy.optimize(lambda z: float(np.sum(residuals(np.asarray(z)) ** 2)))
    cma_time = time.perf_counter() - clock
    cma_rms = float(np.sqrt(strategy.result.fbest)) * problem.torque_scale
    rows.append((ours_time, ours.objective, fd_time, fd_rms, cma_time, cma_rms))
    print(f"start {index}: springbalance {ours_time:6.2f} s rms {ours.objective:.5f} | SciPy FD {fd_time:6.2f} s "
          f"rms {fd_rms:.5f} | CMA-ES {cma_time:6.2f} s rms {cma_rms:.5f}", flush=True)

rows = np.array(rows)
print(f"\n(one-time model build + JIT compile: {setup:.2f} s; budgets: {args.baseline_iterations} iterations for both "
      f"least-squares solvers, {args.cma_evaluations} evaluations for CMA-ES)")
print(f"time per start, median  : springbalance {np.median(rows[:, 0]):.2f} s, SciPy FD {np.median(rows[:, 2]):.2f} s, "
      f"CMA-ES {np.median(rows[:, 4]):.2f} s")
print(f"speed-up (total time)   : {rows[:, 2].sum() / rows[:, 0].sum():.1f}× vs SciPy FD, "
      f"{rows[:, 4].sum() / rows[:, 0].sum():.1f}× vs CMA-ES")
best_ours, best_fd, best_cma = rows[:, 1].min(), rows[:, 3].min(), rows[:, 5].min()
print(f"best rms over the starts: springbalance {best_ours:.5f}, SciPy FD {best_fd:.5f} "
      f"(ours/SciPy {best_ours / best_fd:.4f}), CMA-ES {best_cma:.5f}")
print(f"median rms over starts  : springbalance {np.median(rows[:, 1]):.5f}, SciPy FD {np.median(rows[:, 3]):.5f}, "
      f"CMA-ES {np.median(rows[:, 5]):.5f}")

# ---------------------------------------------------------------- part 2: multi-start with tension constraints
constrained = sb.DesignProblem(mechanism, workspace, springs(keep_tension=True))
clock = time.perf_counter()
result = constrained.solve(starts=args.starts, seed=0, progress=False)
total = time.perf_counter() - clock
times = [record.seconds for record in result.starts]
print(f"\nmulti-start with L ≥ l0: {args.starts} starts in {total:.2f} s; per start median {np.median(times):.2f} s, "
      f"max {np.max(times):.2f} s")
print(result.table())
