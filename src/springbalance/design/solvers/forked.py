"""Tasks of which each decides whether the next is needed, run ahead on worker processes (:func:`run_in_order`).

The clearance fit fits the multi-start's best design, then maybe the next ranked ones: whether fit ``i`` is
needed depends on the fits before it (:func:`~springbalance.design.clearance_round.fall_back`). Each fit is a
chain of single-start solves, one core's work. With ``w`` worker processes the next ``w - 1`` tasks start
before their need is known; a task found not needed is stopped (its process terminated) and its result never
read. Each task computes in its process exactly what it computes alone, so the results are those of running
the needed tasks one after the other, bit for bit.

The workers are forked from this process (they inherit the problem and its compiled functions: nothing but
the results is pickled); they ignore Ctrl-C, which stops them through this process.
"""

from __future__ import annotations

import signal
from typing import Any, Callable, Sequence, TypeVar

from springbalance.design.solvers.pool import _mark_worker, _pool_workers
from springbalance.design.solvers.records import Problem
from springbalance.errors import Interrupted

Result = TypeVar("Result")

_TASKS: Sequence[Callable[[], Any]] = ()  # the tasks a forked worker runs (set before the fork)


def _start_worker() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is this process's: it terminates the workers
    _mark_worker()


def _run_task(index: int) -> Any:
    return _TASKS[index]()


def run_in_order(
    problem: Problem, tasks: Sequence[Callable[[], Result]], needed: Callable[[int, list[Result]], bool]
) -> list[Result]:
    """The results of ``tasks[0]``, ``tasks[1]``, … while ``needed(i, results of the tasks before i)`` holds (it
    is asked from ``i = 1``; task 0 always runs): on the worker processes that a solve of ``problem`` may use
    (:func:`~springbalance.design.solvers.pool.default_workers`), up to one per worker at a time, else here one
    after the other. A task's result must pickle."""
    processes, _ = _pool_workers(problem, None, len(tasks))
    if processes <= 1:
        results: list[Result] = []
        for index, task in enumerate(tasks):
            if index and not needed(index, results):
                break
            results.append(task())
        return results
    return _run_ahead(tasks, needed, processes)


def _run_ahead(
    tasks: Sequence[Callable[[], Result]], needed: Callable[[int, list[Result]], bool], processes: int
) -> list[Result]:
    """:func:`run_in_order` on ``processes`` forked workers, the next tasks started before their need is known."""
    import multiprocessing

    global _TASKS
    _TASKS = tasks
    pool = multiprocessing.get_context("fork").Pool(processes, initializer=_start_worker)
    results: list[Result] = []
    try:
        running = [pool.apply_async(_run_task, (index,)) for index in range(min(processes, len(tasks)))]
        for index in range(len(tasks)):
            if index and not needed(index, results):
                break
            results.append(running[index].get())
            if len(running) < len(tasks):  # keep every worker busy: the next task, its need not yet known
                running.append(pool.apply_async(_run_task, (len(running),)))
        return results
    except KeyboardInterrupt:
        raise Interrupted(f"interrupted: {len(results)} of the tasks had finished") from None
    finally:
        pool.terminate()  # the tasks found not needed, still running (and the idle workers)
        pool.join()
        _TASKS = ()
