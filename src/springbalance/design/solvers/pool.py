"""Worker processes for the starts: how many (:func:`default_workers`, :func:`workers_default`), and the
:class:`_StartRunner` that runs starts here or on a pool of processes forked from this one.

Starts are independent: the workers inherit the problem and its compiled residual (no pickling, no
recompilation), and each start computes exactly what it computes alone, so the result is bit for bit
the sequential one.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import sys
import time
from typing import TYPE_CHECKING, Callable, Iterable, Iterator, Protocol

import numpy as np

from springbalance.design.solvers.records import Problem, StartRecord
from springbalance.design.solvers.residuals import _LeastSquaresResiduals
from springbalance.design.torque_model.threads import count_from_environment, use_one_thread
from springbalance.errors import InputError

WORKERS_ENV = "SPRINGBALANCE_WORKERS"
#: by default, starts go to the pool only when one start is expected to take longer than this [s]
#: (a pool's start-up, forking and collecting, costs 10-20 ms for the demo's process, more for a larger one)
POOL_MIN_SECONDS = 0.1
_DEFAULT_WORKERS: contextvars.ContextVar = contextvars.ContextVar("springbalance_workers", default=None)
_WORKER_SOLVER: _Solver | None = None  # the solver a forked worker runs its starts with (set before the fork)
_IN_WORKER = False

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor  # imported when the pool opens

#: one start for the runner: (index, z0, prepare, the NLP multipliers to go on from or None)
StartTask = tuple[int, np.ndarray, bool, "np.ndarray | None"]


class _Solver(Protocol):
    """What the runner uses of a :class:`~springbalance.design.solvers.multistart._MultiStartSolver` (not
    imported here: it uses this module)."""

    problem: Problem
    method: str
    max_iterations: int
    fixed: np.ndarray

    def prepare(self) -> None: ...

    def run(
        self, index: int, z0: np.ndarray, prepare: bool = True, nlp_multipliers: np.ndarray | None = None
    ) -> StartRecord: ...

    def _matches(self, lam_g: np.ndarray | None) -> bool: ...

    def _residuals(self) -> _LeastSquaresResiduals: ...


def default_workers() -> int:
    """Worker processes of a solve that does not say: ``$SPRINGBALANCE_WORKERS`` when set, else
    ``os.cpu_count()``."""
    value = count_from_environment(WORKERS_ENV)
    if value is not None:
        return value
    return os.cpu_count() or 1


def check_workers(workers: object) -> int | None:
    """``workers`` as an int ≥ 1, or None (the default); InputError otherwise."""
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise InputError(f"workers must be an integer ≥ 1, got {workers!r}")
    return int(workers)


@contextlib.contextmanager
def workers_default(workers: int | None) -> Iterator[None]:
    """Within the block, solves that do not pass ``workers`` use this number (None: no change).
    :meth:`DesignProblem.solve` sets it, so that the solves it makes along the way (coil start,
    clearance fit, wire rounding) use the caller's choice."""
    workers = check_workers(workers)
    token = _DEFAULT_WORKERS.set(workers if workers is not None else _DEFAULT_WORKERS.get())
    try:
        yield
    finally:
        _DEFAULT_WORKERS.reset(token)


def _pool_workers(problem: Problem, workers: int | None, tasks: int) -> tuple[int, bool]:
    """``(processes, asked)``: how many processes may run ``tasks`` starts, and whether the caller
    asked for them (else :class:`_StartRunner` first checks that a start is worth a pool). 1 inside a
    worker (ours, or a daemonic process, which may not have children), without ``fork`` or for one
    task; else ``min(workers, tasks)``."""
    import multiprocessing

    if (
        _IN_WORKER
        or tasks < 2
        or multiprocessing.current_process().daemon
        or sys.platform == "darwin"
        or "fork" not in multiprocessing.get_all_start_methods()
    ):
        return 1, False
    chosen = check_workers(workers)
    if chosen is None:
        chosen = _DEFAULT_WORKERS.get()
    asked = chosen is not None
    if chosen is None:
        chosen = default_workers()
    return max(1, min(chosen, tasks)), asked


def _mark_worker() -> None:
    global _IN_WORKER
    _IN_WORKER = True
    use_one_thread()


def _run_in_worker(
    index: int, z0: np.ndarray, prepare: bool, multipliers: np.ndarray | None, max_iterations: int
) -> StartRecord:
    solver = _WORKER_SOLVER
    assert solver is not None  # set before the fork that made this worker
    solver.max_iterations = max_iterations
    return solver.run(index, z0, prepare, multipliers)


class _StartRunner:
    """Runs starts ``(index, z0, prepare, multipliers)`` with a solver, in order: here, or on a pool of
    ``workers`` processes forked from this one (opened when first needed, closed by :meth:`close`).

    Unless ``asked``, the pool must pay for itself: it opens at once when a start is expected to
    last :data:`POOL_MIN_SECONDS` (IPOPT certain or likely, or one residual evaluation × the iteration budget);
    otherwise the first start runs here, and the pool opens for the others only if it took that long.
    Either way each start computes the same numbers. ``solver``: a
    :class:`~springbalance.design.solvers.multistart._MultiStartSolver` (not imported here: it uses this module).
    """

    def __init__(self, solver: _Solver, workers: int, asked: bool = True) -> None:
        self.solver, self.workers, self.asked = solver, int(workers), bool(asked)
        self._executor: ProcessPoolExecutor | None = None

    def run(self, tasks: Iterable[StartTask], done: Callable[[StartRecord], None] | None = None) -> list[StartRecord]:
        """The records of ``tasks`` in their order; ``done(record)`` is called as each one finishes."""
        tasks, records = list(tasks), []
        if self.workers > 1 and len(tasks) > 1 and self._executor is None and not self.asked:
            self.asked = True  # decided once, for the polish runs too
            if not self._worth_a_pool(tasks):
                clock = time.perf_counter()
                records.append(self._here(tasks.pop(0), done))
                if time.perf_counter() - clock < POOL_MIN_SECONDS:
                    self.workers = 1
        if self.workers <= 1 or len(tasks) <= 1:
            return records + [self._here(task, done) for task in tasks]
        from concurrent.futures import as_completed

        executor = self._pool()
        futures = [executor.submit(_run_in_worker, *task, self.solver.max_iterations) for task in tasks]
        for future in as_completed(futures):
            if done is not None:
                done(future.result())
        return records + [future.result() for future in futures]

    def _here(self, task: StartTask, done: Callable[[StartRecord], None] | None) -> StartRecord:
        record = self.solver.run(*task)
        if done is not None:
            done(record)
        return record

    def _worth_a_pool(self, tasks: list[StartTask]) -> bool:
        """Whether one start is expected to last :data:`POOL_MIN_SECONDS`: IPOPT runs for sure, or
        most likely (the starts go on from IPOPT's multipliers, :meth:`~springbalance.design.solvers.multistart._MultiStartSolver._warm`: least
        squares alone rarely finishes such a start in its short run), or one evaluation of the compiled
        residual times the iteration budget is that long."""
        solver, problem = self.solver, self.solver.problem
        if solver.method == "ipopt" or not problem.objective.least_squares:
            return True
        if any(solver._matches(task[3]) for task in tasks):
            return True
        if not problem.variables.size:
            return False
        residuals = solver._residuals()
        z = np.full(problem.variables.size, 0.5)
        clock = time.perf_counter()
        residuals.normal_equations(z)
        return (time.perf_counter() - clock) * solver.max_iterations >= POOL_MIN_SECONDS

    def _pool(self) -> ProcessPoolExecutor:
        global _WORKER_SOLVER
        if self._executor is None:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            self.solver.prepare()  # the compiled residual is built here, once, and inherited by the workers
            _WORKER_SOLVER = self.solver
            self._executor = ProcessPoolExecutor(
                self.workers, mp_context=multiprocessing.get_context("fork"), initializer=_mark_worker
            )
        return self._executor

    def close(self) -> None:
        """Shut the pool down (if one was opened)."""
        global _WORKER_SOLVER
        if self._executor is not None:
            self._executor.shutdown(wait=True, cancel_futures=True)
            self._executor = None
            _WORKER_SOLVER = None
