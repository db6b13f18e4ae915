"""Start-up: import time, the compiled residual from an empty and from a warm disk cache, the CLI end to end.

Prints, each figure measured in this run (the machine may be shared: compare the ratios):
  1. import time in a fresh interpreter, timed inside it (median of --imports runs, after one
     discarded run that fills a bytecode cache of its own, as an installed package has its .pyc
     even where PYTHONDONTWRITEBYTECODE is set): `import springbalance`, which is lazy (SPEC 1:
     it loads no subpackage and no dependency); `import springbalance; springbalance.DesignProblem`,
     the first use, which loads the library (model, springs, design; numpy, casadi, pinocchio, not
     pydantic, which only the config schema needs); and the dependencies alone (numpy, casadi,
     pinocchio; and with pydantic);
  2. the UR5 problem of bench_ur5.py (4 extension springs, --samples Sobol samples): building its
     compiled residual in a first process on an empty cache (code generation + compiler), then in
     a second process on the same problem (the library is loaded from the cache, no compiler);
  3. one evaluation of the residual and Jacobian at --samples samples, compiled with the cache's
     flags (-O3 -march=native -ffp-contract=off) beside the former JIT flags (-O2);
  4. `springbalance design examples/two_link.yaml --out d.json` end to end, from an empty cache,
     then --cli-runs times from the warm cache, their median (--skip-cli leaves it out); with a
     bytecode cache filled by a discarded run beforehand, as in 1. Alternately with each warm run,
     the same design in one process, timed from importing the CLI to its end, without and with
     `scipy.optimize` imported before the clock: the share of SciPy's import in the demo.

Run: .venv/bin/python benchmarks/bench_startup.py [--samples 4096] [--imports 7] [--skip-cli] [--cli-runs 5]
(make bench-startup; about 3 minutes with the CLI part)
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PYTHON = sys.executable

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=4096)
parser.add_argument("--imports", type=int, default=7)
parser.add_argument("--skip-cli", action="store_true")
parser.add_argument("--cli-runs", type=int, default=5, help="warm-cache runs of the CLI (their median is printed)")
args = parser.parse_args()


def run(command, env=None, cwd=ROOT, replace=False):
    """``(seconds, stdout)`` of ``command``; ``env`` is added to the environment (or is the environment: ``replace``)."""
    clock = time.perf_counter()
    environment = dict(env) if replace else {**os.environ, **(env or {})}
    done = subprocess.run(command, cwd=cwd, env=environment, capture_output=True, text=True)
    seconds = time.perf_counter() - clock
    if done.returncode != 0:
        sys.exit(f"{' '.join(map(str, command))} failed:\n{done.stderr}")
    return seconds, done.stdout


# ---------------------------------------------------------------- 1. import time
def with_bytecode(folder, **extra):
    """This environment with bytecode written to and read from ``folder`` (``PYTHONPYCACHEPREFIX``), even
    where ``PYTHONDONTWRITEBYTECODE`` is set: after a first run fills it, a process imports compiled
    bytecode, as an installed package does (pip compiles it at install)."""
    environment = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
    return {**environment, "PYTHONPYCACHEPREFIX": folder, **extra}


def import_time(statement, bytecode):
    """Median seconds of ``statement`` in a fresh interpreter, timed inside it (and of the whole process), after
    one discarded run that fills the bytecode cache ``bytecode``."""
    code = f"import time; t = time.perf_counter(); {statement}; print(time.perf_counter() - t)"
    runs = [run([PYTHON, "-c", code], with_bytecode(bytecode), replace=True) for _ in range(1 + args.imports)][1:]
    return statistics.median(float(out) for _, out in runs), statistics.median(wall for wall, _ in runs)


with tempfile.TemporaryDirectory(prefix="springbalance-bench-pyc-") as bytecode:
    lazy, lazy_process = import_time("import springbalance", bytecode)
    first_use, first_use_process = import_time("import springbalance; springbalance.DesignProblem", bytecode)
    needed, _ = import_time("import numpy, casadi, pinocchio", bytecode)
    dependencies, _ = import_time("import numpy, casadi, pinocchio, pydantic", bytecode)
print(
    f"import springbalance                              : {lazy:.3f} s (lazy; median of {args.imports}, the process "
    f"with interpreter start and exit {lazy_process:.3f} s)"
)
print(
    f"import springbalance; springbalance.DesignProblem : {first_use:.3f} s (first use: the library; the process "
    f"{first_use_process:.3f} s)"
)
print(
    f"numpy+casadi+pinocchio alone                      : {needed:.3f} s (with pydantic, which the config schema "
    f"needs: {dependencies:.3f} s)"
)

# ---------------------------------------------------------------- 2. compiled residual, cold and warm cache
SETUP = textwrap.dedent(f"""
    import json, time
    import numpy as np
    import springbalance as sb
    from springbalance.design import compile_cache
    from springbalance.design.solvers.residuals import _LeastSquaresResiduals
    box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)
    pairs = [("universe", "upper_arm_link"), ("universe", "forearm_link"),
             ("upper_arm_link", "forearm_link"), ("shoulder_link", "forearm_link")]
    springs = [sb.ExtensionSpring(sb.Anchor(a, box()), sb.Anchor(b, box()), f"s{{i + 1}}",
                                  stiffness=sb.Free(0, 5000), free_length=sb.Free(0.05, 1.0))
               for i, (a, b) in enumerate(pairs)]
    mechanism = sb.Mechanism.from_robot("ur5")
    problem = sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, {args.samples}, seed=1), springs)
    clock = time.perf_counter()
    residuals = _LeastSquaresResiduals(problem)
    seconds = time.perf_counter() - clock
""")
PROBLEM = SETUP + textwrap.dedent("""
    print(json.dumps({"seconds": seconds, "compiles": compile_cache.STATS.compiles,
                      "hits": compile_cache.STATS.hits, "compiler": compile_cache.STATS.compile_seconds}))
""")
EVALUATE = SETUP + textwrap.dedent("""
    import os
    os.environ["SPRINGBALANCE_CFLAGS"] = "-O2"          # the former JIT's flags, in the same process
    former = _LeastSquaresResiduals(problem)
    z = np.full(problem.variables.size, 0.4)
    best = [float("inf"), float("inf")]
    for _ in range(15):                                   # alternate, keep the best of each
        for slot, evaluator in enumerate((residuals.evaluator, former.evaluator)):
            start = time.perf_counter()
            for _ in range(10):
                for _ in evaluator.blocks(z):   # the compiled residual and Jacobian, block by block
                    pass
            best[slot] = min(best[slot], (time.perf_counter() - start) / 10)
    print(json.dumps({"evaluation": best}))
""")
with tempfile.TemporaryDirectory(prefix="springbalance-bench-cache-") as cache:
    environment = {"SPRINGBALANCE_CACHE_DIR": cache}
    cold_wall, out = run([PYTHON, "-c", PROBLEM], environment)
    cold = json.loads(out.strip().splitlines()[-1])
    warm_wall, out = run([PYTHON, "-c", PROBLEM], environment)
    warm = json.loads(out.strip().splitlines()[-1])
print(
    f"compiled residual, 1st process (empty cache): {cold['seconds']:.2f} s to build "
    f"({cold['compiles']} compiled, compiler {cold['compiler']:.2f} s); process {cold_wall:.2f} s"
)
print(
    f"compiled residual, 2nd process (warm cache) : {warm['seconds']:.2f} s to build "
    f"({warm['compiles']} compiled, {warm['hits']} loaded from the cache); process {warm_wall:.2f} s "
    f"-> {cold['seconds'] / warm['seconds']:.1f}x faster, compiler skipped: {warm['compiles'] == 0}"
)

# ---------------------------------------------------------------- 3. evaluation time, cache flags vs -O2
with tempfile.TemporaryDirectory(prefix="springbalance-bench-cache-") as cache:
    output = run([PYTHON, "-c", EVALUATE], {"SPRINGBALANCE_CACHE_DIR": cache})[1]
new, old = json.loads(output.strip().splitlines()[-1])["evaluation"]
print(
    f"residual + Jacobian at {args.samples} samples: {1e3 * new:.2f} ms with the cache's flags "
    f"(-O3 -march=native -ffp-contract=off), {1e3 * old:.2f} ms with -O2 as before (ratio {new / old:.2f}; "
    "best of 15×10, alternated)"
)

# ---------------------------------------------------------------- 4. the CLI end to end
IN_PROCESS = textwrap.dedent("""
    import sys, time
    if {scipy_first}:
        import scipy.optimize   # before the clock: what the demo takes without SciPy's import
    clock = time.perf_counter()
    sys.argv = ["springbalance", *{argv!r}]
    from springbalance import cli
    try:
        cli.main()
    except SystemExit:
        pass
    print(time.perf_counter() - clock)
""")
if not args.skip_cli:
    with (
        tempfile.TemporaryDirectory(prefix="springbalance-bench-cache-") as cache,
        tempfile.TemporaryDirectory(prefix="springbalance-bench-out-") as out,
        tempfile.TemporaryDirectory(prefix="springbalance-bench-pyc-") as bytecode,
        tempfile.TemporaryDirectory(prefix="springbalance-bench-fill-") as fill,
    ):
        command = [
            str(Path(PYTHON).with_name("springbalance")),
            "design",
            "examples/two_link.yaml",
            "--out",
            str(Path(out) / "d.json"),
            "--quiet",
        ]
        run(command, with_bytecode(bytecode, SPRINGBALANCE_CACHE_DIR=fill), replace=True)  # fills the bytecode only
        environment = with_bytecode(bytecode, SPRINGBALANCE_CACHE_DIR=cache)
        cold_cli = run(command, environment, replace=True)[0]
        warm_cli, in_process = [], {False: [], True: []}
        for _ in range(args.cli_runs):  # alternately: the console script, then in one process without and with SciPy
            warm_cli.append(run(command, environment, replace=True)[0])
            for scipy_first in (False, True):
                output = run(
                    [PYTHON, "-c", IN_PROCESS.format(scipy_first=scipy_first, argv=command[1:])],
                    environment,
                    replace=True,
                )[1]
                in_process[scipy_first].append(float(output.strip().splitlines()[-1]))
    print(
        f"springbalance design examples/two_link.yaml --out d.json: {cold_cli:.2f} s from an empty cache, "
        f"{statistics.median(warm_cli):.2f} s from the warm cache (median of {args.cli_runs} runs; "
        f"fastest {min(warm_cli):.2f} s, slowest {max(warm_cli):.2f} s)"
    )
    plain, scipy_before = statistics.median(in_process[False]), statistics.median(in_process[True])
    print(
        f"  the same in one process, from importing the CLI to its end: {plain:.2f} s; with scipy.optimize imported "
        f"before the clock: {scipy_before:.2f} s (SciPy's optimize, which least squares needs, is {plain - scipy_before:.2f} s "
        f"of the demo; medians of {args.cli_runs}, alternated)"
    )
