"""UR5 with four extension springs: springbalance's solver against fair baselines on the same compiled code.

Problem (issue "core engine", must-hold 3): UR5 from example-robot-data; 4 extension
springs ground→upper arm, ground→forearm, upper arm→forearm, shoulder→forearm; every anchor
free in a ±0.3 m box of its body, stiffness in [0, 5000] N/m, free length in [0.05, 1] m;
4,096 Sobol samples of the URDF joint ranges; rms objective.

Part 1 compares, from the same start points and on the same bounded (unconstrained) problem,
every residual compiled to C by the same code path (design/compile_cache.py):
  - springbalance: exact Jacobian of the per-sample model, accumulated as JᵀJ and Jᵀr over blocks of
    samples, start preparation, and SciPy's trust-region reflective method on the compressed
    (n+1-row) residual;
  - SciPy `least_squares` (trf) on the full residual (N·nv rows) with the same compiled exact Jacobian;
  - SciPy `least_squares` (trf) with 2-point finite differences of the compiled residual;
  - CMA-ES (`cma`) on the sum of squares of the compiled residual.
The least-squares solvers share the budget (--baseline-iterations evaluations) and the tolerances of
DesignProblem.solve. For each start and solver the table gives the time, the rms reached and the time
to come within 0.5 % of the best rms any solver reached from that start ("—": never).
Part 2 runs the default multi-start (with the tension constraint L ≥ l0 of every spring) and
prints the time per start and the per-joint table.

Run: .venv/bin/python benchmarks/bench_ur5.py [--samples 4096] [--starts 8] [--compare-starts 4]
                                              [--baseline-iterations 100] [--cma-evaluations 3000]
(make bench; about 5 minutes on 2 cores, most of it in the baselines)
"""

import argparse
import time

import casadi as ca
import numpy as np
from scipy.optimize import least_squares

import springbalance as sb
from springbalance.design.solvers import _MultiStartSolver, start_points
from springbalance.design.torque_model import BlockEvaluator, compiled
from threadpoolctl import threadpool_limits

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=4096)
parser.add_argument("--starts", type=int, default=8)
parser.add_argument("--baseline-iterations", type=int, default=100)
parser.add_argument("--compare-starts", type=int, default=4)
parser.add_argument("--cma-evaluations", type=int, default=3000)
args = parser.parse_args()
WITHIN = 0.005   # "reached": within 0.5 % of the best rms of the start


def springs(keep_tension):
    box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)  # noqa: E731
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

# ---------------------------------------------------------------- part 1: same starts, four solvers
starts = start_points(problem, args.compare_starts, seed=0)
solver = _MultiStartSolver(problem, "least_squares", args.baseline_iterations, 1e-8)  # the default tolerance of DesignProblem.solve
clock = time.perf_counter()
solver.run(0, starts[0])  # the first call builds and compiles (or loads from the disk cache) the model: timed separately
setup = time.perf_counter() - clock
exact = problem.least_squares_cache   # the compiled residual with its exact Jacobian (springbalance's own)

# the compiled residual alone, for the finite differences and CMA-ES (no Jacobian to pay for)
z_symbol = ca.SX.sym("z", problem.variables.size)
data_symbol = ca.SX.sym("data", problem.model.data_size)
lower, upper = problem.variables.bounds()
tau = problem.model.sample(ca.DM(lower) + ca.DM(upper - lower) * z_symbol, data_symbol)[0]
scale = ca.DM(problem.weights / (problem.torque_scale * np.sqrt(workspace.size * mechanism.nv)))
residual_only = BlockEvaluator(compiled(ca.Function("residual_only", [z_symbol, data_symbol], [tau * scale])),
                               problem.data)

trace = []   # (seconds since the solver's start, rms) of every evaluation of the running solver
started = [0.0]


def record(squares):
    rms = float(np.sqrt(max(squares, 0.0))) * problem.torque_scale
    trace.append((time.perf_counter() - started[0], rms))


def residual(z):
    r = residual_only.evaluate(z)[0].reshape(-1)
    record(float(r @ r))
    return r


jacobian_cache = {}


def residual_exact(z):
    r, J = exact.residuals_and_jacobian(z)
    jacobian_cache.clear()
    jacobian_cache[z.tobytes()] = J
    record(float(r @ r))
    return r


def jacobian_exact(z):
    return jacobian_cache.get(z.tobytes()) if z.tobytes() in jacobian_cache else exact.residuals_and_jacobian(z)[1]


normal_equations = exact.normal_equations


def traced_normal_equations(z):
    gram, projected, squares = normal_equations(z)
    record(squares)
    return gram, projected, squares


exact.normal_equations = traced_normal_equations

import cma  # noqa: E402  (benchmark-only dependency)

SOLVERS = ("springbalance", "SciPy exact J", "SciPy FD", "CMA-ES")
options = {"bounds": (0.0, 1.0), "method": "trf", "x_scale": "jac", "ftol": 1e-8, "xtol": 1e-10, "gtol": 1e-10,
           "max_nfev": args.baseline_iterations}


def run(name, z0):
    trace.clear()
    started[0] = time.perf_counter()
    with threadpool_limits(limits=1, user_api="blas"):   # every solver as DesignProblem.solve runs (2 cores, shared)
        solve(name, z0)
    return time.perf_counter() - started[0], list(trace)


def solve(name, z0):
    if name == "springbalance":
        solver.run(0, z0)
    elif name == "SciPy exact J":
        least_squares(residual_exact, z0, jac=jacobian_exact, **options)
    elif name == "SciPy FD":
        least_squares(residual, z0, jac="2-point", **options)
    else:
        strategy = cma.CMAEvolutionStrategy(z0, 0.2, {"bounds": [0, 1], "maxfevals": args.cma_evaluations,
                                                      "verbose": -9, "seed": 1})
        strategy.optimize(lambda z: float(np.sum(residual(np.asarray(z)) ** 2)))


results = {name: [] for name in SOLVERS}   # per start: (seconds, best rms, trace)
for index, z0 in enumerate(starts):
    for name in SOLVERS:
        seconds, history = run(name, z0)
        results[name].append((seconds, min(rms for _, rms in history), history))
    best = min(results[name][-1][1] for name in SOLVERS)
    cells = []
    for name in SOLVERS:
        seconds, rms, history = results[name][-1]
        reached = next((t for t, value in history if value <= (1 + WITHIN) * best), None)
        results[name][-1] = (seconds, rms, reached)
        cells.append(f"{name} {seconds:6.2f} s rms {rms:.5f} reached {'—' if reached is None else f'{reached:.2f} s'}")
    print(f"start {index}: " + " | ".join(cells), flush=True)

exact.normal_equations = normal_equations
print(f"\n(one-time model build + compile or cache load: {setup:.2f} s; budgets: {args.baseline_iterations} "
      f"evaluations for the least-squares solvers, {args.cma_evaluations} for CMA-ES; 'reached': first time within "
      f"{100 * WITHIN:g} % of the best rms of any solver from that start)")
ours = results["springbalance"]
for name in SOLVERS:
    rows = results[name]
    seconds = np.array([row[0] for row in rows])
    reached = [row[2] for row in rows]
    line = (f"{name:<14s}: time per start median {np.median(seconds):6.2f} s, best rms {min(r[1] for r in rows):.5f}, "
            f"median rms {np.median([r[1] for r in rows]):.5f}, reached within {100 * WITHIN:g} % in "
            f"{sum(r is not None for r in reached)}/{len(rows)} starts")
    if name != "springbalance":
        pairs = [(theirs, mine[2]) for theirs, mine in zip(reached, ours) if theirs is not None and mine[2] is not None]
        line += (f"; springbalance is {seconds.sum() / sum(r[0] for r in ours):.1f}× faster in total time"
                 + (f", {np.median([t / m for t, m in pairs]):.1f}× (median) to reach" if pairs else ""))
    print(line)

# ---------------------------------------------------------------- part 2: multi-start with tension constraints
constrained = sb.DesignProblem(mechanism, workspace, springs(keep_tension=True))
clock = time.perf_counter()
result = constrained.solve(starts=args.starts, seed=0, progress=False)
total = time.perf_counter() - clock
times = [start.seconds for start in result.starts]
print(f"\nmulti-start with L ≥ l0: {args.starts} starts in {total:.2f} s; per start median {np.median(times):.2f} s, "
      f"max {np.max(times):.2f} s")
print(result.table())
