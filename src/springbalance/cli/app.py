"""The entry points: :func:`main` (a command line → its exit status) and :func:`run` (the console script)."""

from __future__ import annotations

import argparse
import atexit
import os
import sys
import warnings

from springbalance.cli.formatting import PROG, print_error, print_warning
from springbalance.cli.parser import build_parser
from springbalance.errors import SolverError, SpringBalanceError
from springbalance.model.budget import current_limit, memory_limit


def main(argv: list[str] | None = None) -> int:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    with warnings.catch_warnings():
        warnings.showwarning = print_warning  # one line per warning, like the errors
        return _run(args)


def run() -> None:
    """The console script ``springbalance``: :func:`main`, then exit at once.

    The interpreter's own exit frees every object of the heap one by one (CasADi's and Pinocchio's
    objects, SciPy's modules: 0.1-0.2 s after a design) for memory that the operating system takes
    back anyway, so, as mypy does, the process ends with ``os._exit`` once the output is flushed and
    the exit handlers (``atexit``: a live viewer's server) have run. Every file was closed by the
    command itself (``design`` writes its output atomically), and no thread is left at work: the
    threads still alive (idle workers of a thread pool) end with the process."""
    status = main()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        status = 141
    atexit._run_exitfuncs()  # CPython's: the handlers a normal exit runs, in the same order
    os._exit(status)


def _run(args: argparse.Namespace) -> int:
    """The command's handler under the memory limit; each failure becomes one line on stderr and its exit status
    (1: no feasible design, 2: bad input or file trouble, 130: Ctrl-C, 141: a closed pipe; a design that
    fails a check is the handler's 3). :mod:`springbalance.cli.outcome` lists them."""
    try:
        with memory_limit(getattr(args, "max_memory", None)):
            current_limit()  # a malformed SPRINGBALANCE_MAX_MEMORY is reported before any work
            return args.handler(args)
    except SolverError as error:
        print_error(error)
        return 1
    except SpringBalanceError as error:
        print_error(error)
        return 2
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so that flushing stdout at exit does not fail again
        return 141
    except OSError as error:  # file system trouble while reading or writing (e.g. disk full, permissions)
        detail = f"{error.strerror}: {error.filename!r}" if error.strerror and error.filename else error
        print_error(detail)
        return 2
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except MemoryError:  # an allocation the estimates did not foresee
        print_error(
            "out of memory; lower the sample counts or set a lower --max-memory so that springbalance "
            "refuses such work up front"
        )
        return 2
