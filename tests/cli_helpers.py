"""What the tests of the command line share: its failure lines, and a child process whose Ctrl-C works."""

from __future__ import annotations

import signal


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
