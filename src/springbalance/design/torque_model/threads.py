"""Threads of a block pass (:func:`evaluation_threads`), and integer settings read from the environment."""

from __future__ import annotations

import contextlib
import os
from typing import Iterator

from springbalance.errors import InputError

#: threads of a block pass (:meth:`BlockEvaluator.blocks`): ``1`` evaluates the blocks in the
#: caller's thread; default 2 when the process may use 2 cores (not in a worker process of a pool)
THREADS_ENV = "SPRINGBALANCE_THREADS"


def count_from_environment(name: str) -> int | None:
    """The integer ≥ 1 that environment variable ``name`` holds, None when it is unset or empty;
    :class:`~springbalance.errors.InputError` naming the variable for anything else."""
    text = os.environ.get(name, "").strip()
    if not text:
        return None
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"{name} must be an integer ≥ 1, got {text!r}") from None
    if value < 1:
        raise InputError(f"{name} must be an integer ≥ 1, got {value}")
    return value


_ONE_THREAD = False  # set in the worker processes of a pool of starts (which already use the cores)


def use_one_thread() -> None:
    """Evaluate block passes in the calling thread only, from now on in this process (the pool's
    worker processes call it: the pool already uses the cores)."""
    global _ONE_THREAD
    _ONE_THREAD = True


@contextlib.contextmanager
def one_thread() -> Iterator[None]:
    """Within the block, block passes run in the calling thread only (a study's task, whose
    processes already spread over the cores)."""
    global _ONE_THREAD
    saved, _ONE_THREAD = _ONE_THREAD, True
    try:
        yield
    finally:
        _ONE_THREAD = saved


def evaluation_threads() -> int:
    """Threads of a block pass: ``$SPRINGBALANCE_THREADS`` when set (1 or 2), else 2 when this process
    may run on 2 cores or more and is not a worker process of a pool of starts, else 1."""
    value = count_from_environment(THREADS_ENV)
    if value is not None:
        return min(value, 2)
    if _ONE_THREAD:
        return 1
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    return 2 if cores >= 2 else 1
