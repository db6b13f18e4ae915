"""UR5 with four extension springs: springbalance's solver against SciPy and CMA-ES.

Problem (issue "core engine", must-hold 3): UR5 from example-robot-data; 4 extension
springs ground→upper arm, ground→forearm, upper arm→forearm, shoulder→forearm; every anchor
free in a ±0.3 m box of its body, stiffness in [0, 5000] N/m, free length in [0.05, 1] m;
4,096 Sobol samples of the URDF joint ranges; rms objective.

Part 1 compares, from the same start and on the same bounded (unconstrained) problem:
  - springbalance: exact Jacobian of the CasADi per-sample model (JIT-compiled when a C compiler
    is available) + bounded Levenberg–Marquardt;
  - SciPy `least_squares` (trf) with 2-point finite differences on the same residuals;
  - CMA-ES (`cma`) on the same scaled variables.
Part 2 runs the default multi-start (with the tension constraint L ≥ l0 of every spring) and
prints the time per start and the per-joint table.

Run: .venv/bin/python benchmarks/bench_ur5.py [--samples 4096] [--starts 8] [--baseline-iterations 100]
"""

import argparse
import time

import numpy as np
from scipy.optimize import least_squares

import springbalance as sb
from springbalance.solve import _MultiStartSolver, start_points

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=4096)
parser.add_argument("--starts", type=int, default=8)
parser.add_argument("--baseline-iterations", type=int, default=100)
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

# ---------------------------------------------------------------- part 1: same start, three solvers
z0 = start_points(problem, 2, seed=0)[1]
solver = _MultiStartSolver(problem, "least_squares", args.baseline_iterations, 1e-6)
clock = time.perf_counter()
solver.run(0, z0)  # first call builds and JIT-compiles the Jacobian: timed separately
setup = time.perf_counter() - clock
clock = time.perf_counter()
ours = solver.run(0, z0)
ours_time = time.perf_counter() - clock
print(f"\nspringbalance LM     : {ours_time:7.2f} s  rms {ours.objective:.5f} N·m  ({ours.iterations} iterations, "
      f"{ours.status}; one-time model build + compile {setup:.2f} s)")


def residuals(z):  # the same scaled residuals, evaluated numerically (CasADi virtual machine, no JIT)
    evaluation = problem.evaluate(problem.scale(z))
    return (evaluation.tau * problem.weights).reshape(-1) / (problem.torque_scale * np.sqrt(evaluation.tau.size))


clock = time.perf_counter()
scipy_result = least_squares(residuals, z0, jac="2-point", bounds=(0.0, 1.0), method="trf",
                             max_nfev=args.baseline_iterations)
scipy_time = time.perf_counter() - clock
scipy_rms = float(np.sqrt(2 * scipy_result.cost)) * problem.torque_scale
print(f"SciPy FD least_sq    : {scipy_time:7.2f} s  rms {scipy_rms:.5f} N·m  ({scipy_result.nfev} iterations, "
      f"{scipy_result.message})")

import cma  # noqa: E402  (benchmark-only dependency)

clock = time.perf_counter()
strategy = cma.CMAEvolutionStrategy(z0, 0.2, {"bounds": [0, 1], "maxfevals": args.cma_evaluations, "verbose": -9,
                                              "seed": 1})
strategy.optimize(lambda z: float(np.sum(residuals(np.asarray(z)) ** 2)))
cma_time = time.perf_counter() - clock
cma_rms = float(np.sqrt(strategy.result.fbest)) * problem.torque_scale
print(f"CMA-ES               : {cma_time:7.2f} s  rms {cma_rms:.5f} N·m  ({strategy.result.evaluations} evaluations)")

print(f"\nspeed-up vs SciPy FD : {scipy_time / ours_time:6.1f}×   objective ratio ours/SciPy {ours.objective / scipy_rms:.4f}")
print(f"speed-up vs CMA-ES   : {cma_time / ours_time:6.1f}×   objective ratio ours/CMA-ES {ours.objective / cma_rms:.4f}")

# ---------------------------------------------------------------- part 2: multi-start with tension constraints
constrained = sb.DesignProblem(mechanism, workspace, springs(keep_tension=True))
clock = time.perf_counter()
result = constrained.solve(starts=args.starts, seed=0, progress=False)
total = time.perf_counter() - clock
times = [record.seconds for record in result.starts]
print(f"\nmulti-start with L ≥ l0: {args.starts} starts in {total:.2f} s; per start median {np.median(times):.2f} s, "
      f"max {np.max(times):.2f} s")
print(result.table())
