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
      (``export`` and ``order`` write their files only with ``--partial`` too; ``evaluate``, ``report``
      and ``view`` of such a design exit 3 too; ``clearance`` when a spring comes closer than the margin)
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


#: failures that another start of the same search may avoid: the fit to the arm, the verification's re-solves and the
#: hold of a joint are local solves whose end depends on where the multi-start left the design
SEARCH_DEPENDENT = ("not_converged", "overlap", "not_verified", "worse_joint")
#: the hint under such failures of a design solved at one seed
SEEDS_HINT = (
    "the fit to the arm is a chain of local solves whose end depends on where the search starts: another seed may "
    "pass (--seeds 0-4 solves at five seeds and keeps the best design that passes)"
)


def print_failures(failures: Sequence[Flag], consequence: str | None = None, one_seed: bool = False) -> None:
    """One line per failure on stderr: ``springbalance: failure: [kind] message``; for a design solved at
    ``one_seed`` with a failure of :data:`SEARCH_DEPENDENT` kind, ``springbalance: hint:`` :data:`SEEDS_HINT`; then,
    given a ``consequence`` (what the command did about them), ``springbalance: the design fails N check(s);
    <consequence>``."""
    for flag in failures:
        print(f"{PROG}: failure: [{flag.kind}] {' '.join(flag.message.split())}", file=sys.stderr)
    if one_seed and any(flag.kind in SEARCH_DEPENDENT for flag in failures):
        print(f"{PROG}: hint: {SEEDS_HINT}", file=sys.stderr)
    if failures and consequence is not None:
        print(f"{PROG}: the design fails {len(failures)} check(s); {consequence}", file=sys.stderr)


def failure_summary(failures: Sequence[Flag]) -> str:
    """Why a file is marked partial: ``it fails N check(s): kind, kind`` (the kinds sorted, once each)."""
    return f"it fails {len(failures)} check(s): {', '.join(sorted({flag.kind for flag in failures}))}"


def outcome(failures: Sequence[Flag]) -> int:
    """The exit status of a command that found (or loaded) a design with ``failures``: 0 or 3."""
    return FAILED_CHECK if failures else OK
