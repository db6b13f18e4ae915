"""The least-squares path: one evaluation of the residual and Jacobian, one normal-equations pass, one start.

Problem: UR5 with the 4 extension springs of bench_ur5.py (anchors in ±0.3 m boxes, stiffness and free
length free, no tension constraint), rms objective, the compiled residual of DesignProblem's
least-squares solver (solvers.residuals._LeastSquaresResiduals). Two builds of the same residual, in this process:

  - "CasADi map": the compiled library of CasADi's C code, evaluated by CasADi's serial map over
    each block of samples (BlockEvaluator(..., kernel=False): the path before the block kernel);
  - "kernel": the block kernel (block_kernel.block_kernel_code: 4 samples at once in vector
    registers, x-only operations once per call; its own small library), evaluated block by block,
    with 1 thread and with 2 (a helper thread evaluates block k+1 while JᵀJ of block k is summed).

Figures (each the minimum over --repeats, the variants alternated so that the machine's load hits
them alike; CPU/wall is the process's CPU time over the wall time of those runs):
  1. one evaluation of residual + Jacobian (all blocks) at --samples (default 4,096; goal ≤ 1.6 ms);
  2. one normal-equations pass (JᵀJ, Jᵀr, rᵀr summed over the blocks) at --samples and at
     --large (default 100,000);
  3. one start at --large, --iterations (100) at most: measured with the kernel (threads as
     SPRINGBALANCE_THREADS says, default 2), projected from the pass time for the others (goal ≤ 5 s);
  4. whether JᵀJ, Jᵀr, rᵀr and the start's design are bit for bit the same on every path.
Also, for the record: CasADi's map with 2 threads ("thread") against its serial map, and JᵀJ of one
block by NumPy's matmul against SciPy's dsyrk (1 BLAS thread).

Run: .venv/bin/python benchmarks/bench_evaluation.py [--samples 4096] [--large 100000] [--iterations 100]
                                                    [--repeats 30] [--skip-start]
(about 2 minutes on 2 cores, most of it in the starts at 100,000 samples)
"""

import argparse
import os
import resource
import time

import numpy as np
from threadpoolctl import threadpool_limits

import springbalance as sb
from springbalance.design import torque_model
from springbalance.design.solvers import start_points
from springbalance.design.solvers.multistart import _MultiStartSolver
from springbalance.design.solvers.residuals import _LeastSquaresResiduals
from springbalance.design.torque_model import BlockEvaluator

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--samples", type=int, default=4096)
parser.add_argument("--large", type=int, default=100_000)
parser.add_argument("--iterations", type=int, default=100)
parser.add_argument("--repeats", type=int, default=30)
parser.add_argument("--skip-start", action="store_true", help="leave out the measured starts at --large samples")
args = parser.parse_args()

mechanism = sb.Mechanism.from_robot("ur5")
box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)  # noqa: E731
pairs = [
    ("universe", "upper_arm_link"),
    ("universe", "forearm_link"),
    ("upper_arm_link", "forearm_link"),
    ("shoulder_link", "forearm_link"),
]


def problem_of(samples):
    springs = [
        sb.ExtensionSpring(
            sb.Anchor(a, box()),
            sb.Anchor(b, box()),
            f"s{i + 1}",
            stiffness=sb.Free(0, 5000),
            free_length=sb.Free(0.05, 1.0),
            keep_tension=False,
        )
        for i, (a, b) in enumerate(pairs)
    ]
    return sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, samples, seed=1), springs)


def residuals_of(problem, kernel):
    """The solver's residual, evaluated with or without the block kernel."""
    residuals = _LeastSquaresResiduals(problem)
    if not kernel:
        residuals.evaluator = BlockEvaluator(residuals.function, problem.data, kernel=False)
    return residuals


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


class Threads:
    """SPRINGBALANCE_THREADS within the block."""

    def __init__(self, threads):
        self.threads = threads

    def __enter__(self):
        self.saved = os.environ.get(torque_model.THREADS_ENV)
        os.environ[torque_model.THREADS_ENV] = str(self.threads)

    def __exit__(self, *exc):
        if self.saved is None:
            os.environ.pop(torque_model.THREADS_ENV, None)
        else:
            os.environ[torque_model.THREADS_ENV] = self.saved


def compare(variants, repeats):
    """``{name: (best seconds, CPU/wall)}`` of the variants ``{name: (threads, call)}``, alternated."""
    times = {name: [] for name in variants}
    cpu = {name: 0.0 for name in variants}
    for _ in range(repeats):
        for name, (threads, call) in variants.items():
            with Threads(threads):
                clock, used = time.perf_counter(), cpu_seconds()
                call()
                times[name].append(time.perf_counter() - clock)
                cpu[name] += cpu_seconds() - used
    return {name: (min(times[name]), cpu[name] / sum(times[name])) for name in variants}


def evaluation(residuals, z):
    def run():
        for _ in residuals.evaluator.blocks(z):
            pass

    return run


def normal_pass(residuals, z):
    def run():
        residuals._normal_key = None  # no cached answer
        residuals.normal_equations(z)

    return run


def same_normal_equations(a, b, z):
    first, second = (normal_pass(r, z)() or r.normal_equations(z) for r in (a, b))
    return all(np.array_equal(x, y) for x, y in zip(first, second))


def report(title, figures, samples, reference="CasADi map"):
    base = figures[reference][0]
    for name, (seconds, ratio) in figures.items():
        print(
            f"  {title} {name:<18s}: {1e3 * seconds:8.3f} ms ({1e9 * seconds / samples:6.1f} ns/sample), "
            f"{base / seconds:4.2f}× the CasADi map, CPU/wall {ratio:.2f}",
            flush=True,
        )


with threadpool_limits(limits=1, user_api="blas"):  # as DesignProblem.solve runs
    # ------------------------------------------------------------ 1, 2: --samples
    problem = problem_of(args.samples)
    clock = time.perf_counter()
    old = residuals_of(problem, kernel=False)
    old_seconds = time.perf_counter() - clock
    clock = time.perf_counter()
    new = residuals_of(problem, kernel=True)
    new_seconds = time.perf_counter() - clock
    if new.evaluator._kernel is None:
        raise SystemExit("no block kernel (no C compiler with vector extensions?)")
    z = np.random.default_rng(0).random(problem.variables.size)
    print(
        f"UR5, 4 springs, {problem.variables.size} variables, blocks of {new.evaluator.block} samples; "
        f"build (compile or cache load): residual {old_seconds:.2f} s, then with its kernel {new_seconds:.2f} s; "
        f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}"
    )
    figures = compare({"CasADi map": (1, evaluation(old, z)), "kernel": (1, evaluation(new, z))}, args.repeats)
    print(f"1. one evaluation of residual + Jacobian at {args.samples} samples (goal ≤ 1.6 ms):")
    report("evaluation", figures, args.samples)
    figures = compare(
        {
            "CasADi map": (1, normal_pass(old, z)),
            "kernel, 1 thread": (1, normal_pass(new, z)),
            "kernel, 2 threads": (2, normal_pass(new, z)),
        },
        args.repeats,
    )
    print(f"2. one normal-equations pass at {args.samples} samples:")
    report("pass", figures, args.samples)
    with Threads(2):
        identical = same_normal_equations(old, new, z)
    print(f"   JᵀJ, Jᵀr, rᵀr bit for bit the same (CasADi map vs kernel with 2 threads): {identical}")

    # for the record: CasADi's own 2-thread map, and dsyrk against matmul
    from scipy.linalg.blas import dsyrk

    n = problem.workspace.size
    maps = {}
    for mode in ("serial", "thread"):
        mapped = old.function.map(n, mode, 2) if mode == "thread" else old.function.map(n, "serial")
        buffer, trigger = mapped.buffer()
        shared = np.tile(z, (n, 1))
        data = np.asfortranarray(problem.data).reshape(-1, order="F")
        outputs = [np.zeros(old.function.nnz_out(i) * n) for i in range(old.function.n_out())]
        buffer.set_arg(0, memoryview(shared.reshape(-1)))
        buffer.set_arg(1, memoryview(data))
        for i, out in enumerate(outputs):
            buffer.set_res(i, memoryview(out))
        maps[mode] = (1, lambda trigger=trigger, keep=(buffer, shared, data, outputs): trigger())
    figures = compare(maps, max(args.repeats // 3, 3))
    print(
        f"   (CasADi's map of all {n} samples: 2 threads {1e3 * figures['thread'][0]:.3f} ms, CPU/wall "
        f"{figures['thread'][1]:.2f}, against serial {1e3 * figures['serial'][0]:.3f} ms: "
        f"{figures['serial'][0] / figures['thread'][0]:.2f}×)"
    )
    jacobian = next(iter(new.evaluator.blocks(z)))[2][1]
    J = jacobian.reshape(-1, problem.variables.size)
    figures = compare({"matmul": (1, lambda: J.T @ J), "dsyrk": (1, lambda: dsyrk(1.0, J.T, trans=0))}, args.repeats)
    print(
        f"   (JᵀJ of one block of {jacobian.shape[0]} samples: NumPy matmul {1e6 * figures['matmul'][0]:.1f} µs, "
        f"SciPy dsyrk {1e6 * figures['dsyrk'][0]:.1f} µs: {figures['matmul'][0] / figures['dsyrk'][0]:.2f}×; "
        f"the summation is solvers.py's)"
    )

    # ------------------------------------------------------------ 2, 3: --large
    large = problem_of(args.large)
    old_large, new_large = residuals_of(large, kernel=False), residuals_of(large, kernel=True)
    z = np.random.default_rng(0).random(large.variables.size)
    passes = compare(
        {
            "CasADi map": (1, normal_pass(old_large, z)),
            "kernel, 1 thread": (1, normal_pass(new_large, z)),
            "kernel, 2 threads": (2, normal_pass(new_large, z)),
        },
        max(args.repeats // 6, 3),
    )
    print(f"2. one normal-equations pass at {args.large} samples:")
    report("pass", passes, args.large)
    with Threads(2):
        identical = same_normal_equations(old_large, new_large, z)
    print(f"   JᵀJ, Jᵀr, rᵀr bit for bit the same: {identical}")
    print(f"3. one start at {args.large} samples, {args.iterations} iterations (goal ≤ 5 s):")
    for name, (seconds, _) in passes.items():
        print(
            f"   projected {name:<18s}: {args.iterations} passes × {1e3 * seconds:.1f} ms = "
            f"{args.iterations * seconds:.2f} s"
        )
    if not args.skip_start:
        start = start_points(large, 1, 0)[0]
        designs = {}
        for name, residuals, threads in (
            ("kernel, 2 threads", new_large, 2),
            ("kernel, 1 thread", new_large, 1),
            ("CasADi map", old_large, 1),
        ):
            large.least_squares_cache = residuals
            residuals._normal_key = None
            solver = _MultiStartSolver(large, "least_squares", args.iterations, 1e-8)
            solver.prepare()
            with Threads(threads):
                clock, used = time.perf_counter(), cpu_seconds()
                record = solver.run(0, start)
                seconds, cpu = time.perf_counter() - clock, cpu_seconds() - used
            designs[name] = (record.x, record.objective)
            print(
                f"   measured  {name:<18s}: {seconds:6.2f} s ({record.iterations} iterations, "
                f"{1e3 * seconds / max(record.iterations, 1):.1f} ms each), CPU/wall {cpu / seconds:.2f}, "
                f"rms {record.objective:.9f}",
                flush=True,
            )
        first = next(iter(designs.values()))
        print(
            f"4. designs bit for bit the same on the three paths: "
            f"{all(np.array_equal(x, first[0]) and value == first[1] for x, value in designs.values())}"
        )
