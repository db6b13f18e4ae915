"""The command line's exit statuses, and what it prints about a design that fails a check.

====  ==========================================================================================
code  meaning
====  ==========================================================================================
0     success (a design that passes every check)
1     no feasible design: no start of the solve met the constraints (``SolverError``)
2     bad input, or trouble reading or writing a file (one line on stderr names the culprit)
3     a design was found but fails a check (``infeasible``, ``not_converged``, ``unbuildable``,
      ``overlap``, ``worse_joint`` on a weighted joint, ``not_verified``, ``partial``): the report is
      printed, one line per failure on stderr, and ``--out`` is written only with ``--partial``
      (``evaluate`` and ``report`` of such a design exit 3 too, ``order`` writes nothing without
      ``--partial``; ``clearance`` when a spring comes closer than the margin)
130   interrupted (Ctrl-C)
141   the output pipe was closed (e.g. ``| head``)
====  ==========================================================================================
"""

from __future__ import annotations

import sys
from typing import Sequence

from springbalance.cli.formatting import PROG
from springbalance.results.flag import Flag

OK = 0
NO_DESIGN = 1
BAD_INPUT = 2
FAILED_CHECK = 3
INTERRUPTED = 130
CLOSED_PIPE = 141


def print_failures(failures: Sequence[Flag]) -> None:
    """One line per failure on stderr: ``springbalance: failure: [kind] message``."""
    for flag in failures:
        print(f"{PROG}: failure: [{flag.kind}] {' '.join(flag.message.split())}", file=sys.stderr)


def outcome(failures: Sequence[Flag]) -> int:
    """The exit status of a command that found (or loaded) a design with ``failures``: 0 or 3."""
    return FAILED_CHECK if failures else OK
