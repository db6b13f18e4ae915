"""Where a study's tasks run: in this process, or on a Dask ``distributed`` cluster.

:func:`make_client` opens a ``Client``: on a running scheduler given by address, or on a new
``LocalCluster`` of one single-threaded worker process per core. :func:`execute` submits a list of
tasks (:mod:`springbalance.explore.task`) and yields each result as it finishes; without a client
they are solved one after another in this process.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterator, Protocol, Sequence

from springbalance.errors import InputError
from springbalance.explore.task import Task, solve_task, task_payload

if TYPE_CHECKING:
    from distributed import Client

#: seconds to wait for a scheduler given by address
CONNECT_TIMEOUT = 10.0


class ProgressBar(Protocol):
    """What a study's run reports its progress to (a ``tqdm`` bar, or nothing)."""

    def update(self, n: int = 1) -> Any: ...

    def close(self) -> Any: ...


class _NoBar:
    def update(self, n: int = 1) -> None:
        pass

    def close(self) -> None:
        pass


def progress_bar(total: int, show: bool, desc: str = "topologies") -> ProgressBar:
    """A ``tqdm`` bar of ``total`` tasks (labelled ``desc``) when ``show`` (and there is something to show), else a
    silent one."""
    if not show or total <= 0:
        return _NoBar()
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="task", leave=False)


def execute(
    tasks: Sequence[Task],
    client: Client | None,
    base_dir: Path,
    starts: int,
    seed: int,
    seeds: Sequence[int] | None = None,
) -> Iterator[dict[str, Any]]:
    """Yield each task's result as it finishes (in this process, or on the Dask cluster): solved at ``seed``, or at
    each of ``seeds`` with the best design kept."""
    payloads = [task_payload(task, base_dir, starts, seed, seeds) for task in tasks]
    if client is None:
        for payload in payloads:
            yield solve_task(payload)
        return
    from dask.distributed import as_completed

    futures = [
        client.submit(solve_task, payload, key=f"springbalance-{payload['id']}", pure=False) for payload in payloads
    ]
    for future in as_completed(futures):
        yield future.result()


def make_client(scheduler: str | None = None, workers: int | None = None, timeout: float = CONNECT_TIMEOUT) -> Client:
    """A Dask ``Client``: on the scheduler at ``scheduler`` (``tcp://host:port``), or on a new
    ``LocalCluster`` of ``workers`` processes (default: one per core), one thread each;
    ``timeout`` [s] bounds the wait for a scheduler given by address."""
    import logging

    from dask.distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            return Client(scheduler, timeout=f"{timeout}s")
        except (OSError, TimeoutError, ValueError) as error:
            raise InputError(
                f"cannot reach the Dask scheduler at {scheduler!r} within {timeout:g} s "
                f"({type(error).__name__}: {str(error).splitlines()[0] if str(error) else 'no answer'})"
            ) from None
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InputError(f"workers must be an integer ≥ 1, got {workers!r}")
    cluster = LocalCluster(
        n_workers=workers or os.cpu_count() or 1,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    )
    return Client(cluster)
