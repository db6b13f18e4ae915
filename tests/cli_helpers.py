"""What the tests of the command line share: its failure lines, and a child process whose Ctrl-C works."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from typing import Callable


def failure_lines(err: str) -> list[str]:
    """The ``springbalance: failure: [kind] ...`` lines of a command's stderr."""
    return [line for line in err.splitlines() if line.startswith("springbalance: failure: ")]


def failure_kinds(err: str) -> list[str]:
    """The kinds of the failure lines of ``err``, in order."""
    return [line.split("[", 1)[1].split("]", 1)[0] for line in failure_lines(err)]


def default_ctrl_c() -> None:
    """In the child before it starts: SIGINT unblocked and at its default, whatever the test process inherited
    (a blocked or ignored SIGINT is inherited across exec, and Python then never raises KeyboardInterrupt)."""
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def until_ctrl_c(
    argv: list[str], while_running: Callable[[subprocess.Popen, str], None] | None = None
) -> tuple[int, str, str]:
    """Run ``springbalance *argv`` as a real process until its first line of output, call
    ``while_running(process, first_line)``, then press Ctrl-C (SIGINT): (exit status, the rest of stdout,
    stderr). A process that outlives the test is killed, not left behind."""
    process = subprocess.Popen(
        [sys.executable, "-m", "springbalance", *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=default_ctrl_c,
    )
    try:
        first = process.stdout.readline() if process.stdout is not None else ""
        assert first, process.communicate()
        if while_running is not None:
            while_running(process, first)
        time.sleep(0.3)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    return process.returncode, out, err
