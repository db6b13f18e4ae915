"""The IPOPT path: derivatives through the per-sample structure on a working set of rows, against the plain NLP.

Two problems, each solved once from the same start by both ways, each in a fresh process (so that
the peak RSS, measured after the problem is built, is that of the solve alone):

  1. UR5 from example-robot-data, the 4 extension springs of bench_ur5.py, objective ``peak``
     (epigraph: 2·N·nv rows), --samples Sobol samples (default 4,096); start: the rms least-squares
     design of one start, as the solver warm-starts IPOPT;
  2. examples/two_link.yaml: three helical coils whose stress, hook, index and initial-tension
     rows hold at every one of its 128 samples, objective ``rms``; start: the least-squares
     (augmented Lagrangian) design of the configuration's first guess, as the solver hands it on.

"plain": ``DesignProblem.build()`` given to ``casadi.nlpsol`` with CasADi's exact Hessian of the
mapped MX graph and every row (the path before this change). "structured":
``springbalance.design.structured_nlp.StructuredNlp.solve`` (what ``DesignProblem.solve`` runs now).
Both with the solver's options (tol 1e-8, adaptive barrier) and the same iteration budget.

Run: .venv/bin/python benchmarks/bench_ipopt.py [--samples 4096] [--iterations 100] [--skip-plain-ur5]
(make bench-ipopt; about 4 minutes on 2 cores, most of it the plain NLP on UR5)
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=4096)
parser.add_argument("--iterations", type=int, default=100)
parser.add_argument("--skip-plain-ur5", action="store_true", help="leave out the slow plain NLP on UR5")
parser.add_argument("--child", nargs=2, metavar=("CASE", "WAY"), help=argparse.SUPPRESS)
args = parser.parse_args()


def ur5_problem():
    import springbalance as sb
    from springbalance.design.solvers import solve_problem

    def box():
        return sb.Free([-0.3] * 3, [0.3] * 3)

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
        )
        for i, (a, b) in enumerate(pairs)
    ]
    mechanism = sb.Mechanism.from_robot("ur5")
    workspace = sb.Workspace.sobol(mechanism, args.samples, seed=1)
    start = solve_problem(sb.DesignProblem(mechanism, workspace, springs), starts=1, workers=1, polish_iterations=0).x
    return sb.DesignProblem(mechanism, workspace, springs, objective="peak"), start


def two_link_problem():
    from springbalance.design.solvers.multistart import _MultiStartSolver
    from springbalance.io.config import load_config

    problem = load_config(ROOT / "examples" / "two_link.yaml").problem
    solver = _MultiStartSolver(problem, "auto", args.iterations, 1e-8)
    z = solver._least_squares(problem.unscale(problem.variables.start))[0]
    return problem, problem.scale(z)


def child(case, way):
    """Solve case ``case`` the ``way`` way; print one JSON line."""
    import casadi as ca
    import numpy as np

    from springbalance.design.structured_nlp import StructuredNlp

    problem, x = ur5_problem() if case == "ur5" else two_link_problem()
    evaluation = problem.evaluate(x)
    before = problem.objective_value(evaluation)
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    options = {
        "print_time": False,
        "ipopt.print_level": 0,
        "ipopt.sb": "yes",
        "ipopt.tol": 1e-8,
        "ipopt.acceptable_tol": 1e-8,
        "ipopt.mu_strategy": "adaptive",
    }
    clock = time.perf_counter()
    if way == "plain":
        nlp = problem.build()
        solver = ca.nlpsol(
            "plain", "ipopt", {"x": nlp.z, "f": nlp.cost, "g": nlp.rows}, {**options, "ipopt.max_iter": args.iterations}
        )
    else:
        structured = StructuredNlp(problem)
        nlp = structured.nlp
    start = np.clip(problem.unscale(x), 0.0, 1.0)
    if nlp.size > nlp.n_design:
        start = np.concatenate([start, nlp.extra_start(evaluation.tau * problem.weights)])
    built = time.perf_counter() - clock
    if way == "plain":
        solution = solver(x0=start, lbx=nlp.lower, ubx=nlp.upper, lbg=0.0, ubg=np.inf)
        w, stats = np.array(solution["x"]).reshape(-1), solver.stats()
        status, iterations = stats["return_status"], stats["iter_count"]
    else:
        w, status, iterations, _ = structured.solve(start, nlp.lower, nlp.upper, options, args.iterations)
    seconds = time.perf_counter() - clock
    after = problem.evaluate(problem.scale(np.clip(w[: nlp.n_design], 0.0, 1.0)))
    print(
        json.dumps(
            {
                "seconds": seconds,
                "build": built,
                "status": status,
                "iterations": int(iterations),
                "before": before,
                "after": problem.objective_value(after),
                "violation": after.max_violation,
                "rows": nlp.n_rows,
                "variables": nlp.size,
                "rss_mib": (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) / 1024,
            }
        )
    )


def run(case, way):
    command = [
        sys.executable,
        __file__,
        "--child",
        case,
        way,
        "--samples",
        str(args.samples),
        "--iterations",
        str(args.iterations),
    ]
    done = subprocess.run(command, capture_output=True, text=True, env={**os.environ, "SPRINGBALANCE_WORKERS": "1"})
    if done.returncode != 0:
        sys.exit(f"{case} {way} failed:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


if args.child:
    child(*args.child)
    sys.exit(0)

for case, title in (
    ("ur5", f"UR5, 4 extension springs, objective peak, {args.samples} samples"),
    ("two_link", "examples/two_link.yaml, 3 helical coils with per-sample stress rows, objective rms"),
):
    print(title)
    results = {}
    for way in ("structured", "plain"):
        if way == "plain" and case == "ur5" and args.skip_plain_ur5:
            continue
        result = results[way] = run(case, way)
        print(
            f"  {way:10s}: {result['seconds']:7.2f} s (NLP built in {result['build']:.2f} s), "
            f"{result['iterations']:4d} iterations, {result['status']}; objective {result['before']:.5g} -> "
            f"{result['after']:.5g} (violation {result['violation']:.1e}); peak RSS +{result['rss_mib']:.0f} MiB; "
            f"{result['rows']} rows, {result['variables']} variables"
        )
    if len(results) == 2:
        new, old = results["structured"], results["plain"]
        better = "the same or better" if new["after"] <= old["after"] * (1 + 1e-6) else "worse"
        print(
            f"  -> {old['seconds'] / new['seconds']:.1f}x less time, {old['rss_mib'] / max(new['rss_mib'], 1):.1f}x "
            f"less memory, objective {better} ({new['after']:.5g} vs {old['after']:.5g})"
            + ("  [goal for UR5: >= 10x time, >= 5x memory, same or better peak]" if case == "ur5" else "")
        )
