"""The ``springbalance`` command-line tool.

::

    springbalance design CONFIG.yaml --out design.json [--starts N] [--seed S] [--method M] [--quiet]
    springbalance evaluate design.json [--workspace WORKSPACE.yaml]
    springbalance robots

Exit status: 0 on success, 1 when the solver finds no feasible design, 2 on bad input
(unknown key, body or joint, malformed file, missing file, ...). Errors are printed as one
line, ``springbalance: error: <message>``, on stderr, without a traceback; ``design``
writes its output file atomically and only after a successful solve, so a failed run
leaves no (partial) output file behind.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from . import __version__
from .errors import InputError, SolverError, SpringBalanceError

PROG = "springbalance"


def main(argv: list[str] | None = None) -> int:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.handler(args)
    except SolverError as error:
        _print_error(error)
        return 1
    except SpringBalanceError as error:
        _print_error(error)
        return 2
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so that flushing stdout at exit does not fail again
        return 141
    except OSError as error:  # file system trouble while reading or writing (e.g. disk full, permissions)
        detail = f"{error.strerror}: {error.filename!r}" if error.strerror and error.filename else error
        _print_error(detail)
        return 2
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130


def build_parser() -> argparse.ArgumentParser:
    from .solve import METHODS

    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Design gravity-balancing springs for robot arms described by URDF.",
        epilog="Exit status: 0 success, 1 solver found no feasible design, 2 bad input. "
               f"Run '{PROG} COMMAND --help' for the options of a command.")
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    design = commands.add_parser(
        "design", help="solve the design problem of a config file and save the design",
        description="Build the design problem described by CONFIG (YAML or JSON), solve it with a "
                    "multi-start, print the report and save the design as JSON.")
    design.add_argument("config", metavar="CONFIG", help="config file (.yaml, .yml or .json)")
    design.add_argument("--out", "-o", required=True, metavar="DESIGN.json",
                        help="where to save the design (written only when the solve succeeds)")
    design.add_argument("--starts", type=_positive_int, metavar="N",
                        help="number of starts of the multi-start (overrides solve.starts)")
    design.add_argument("--seed", type=_nonnegative_int, metavar="S",
                        help="seed of the start points (overrides solve.seed)")
    design.add_argument("--method", choices=METHODS, help="solver backend (overrides solve.method)")
    design.add_argument("--quiet", "-q", action="store_true", help="print nothing on success, no progress bar")
    design.set_defaults(handler=_design)

    evaluate = commands.add_parser(
        "evaluate", help="print the report of a saved design",
        description="Load a design saved by 'springbalance design' and print its report, on the "
                    "workspace it was designed on or on another one.")
    evaluate.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    evaluate.add_argument("--workspace", "-w", metavar="WORKSPACE.yaml",
                          help="YAML/JSON file with a 'workspace:' mapping (a whole config works too) "
                               "to evaluate the design on instead of its own workspace")
    evaluate.set_defaults(handler=_evaluate)

    robots = commands.add_parser(
        "robots", help="list the robots of example-robot-data",
        description="List the robot names accepted by 'mechanism: {robot: NAME}' in a config.")
    robots.add_argument("--paths", action="store_true", help="also print the URDF file of each robot")
    robots.set_defaults(handler=_robots)
    return parser


# ---------------------------------------------------------------------- commands
def _design(args) -> int:
    from .config import load_config

    out = Path(args.out)
    _check_output(out)
    config = load_config(args.config)
    progress = False if args.quiet else None
    result = config.solve(starts=args.starts, seed=args.seed, method=args.method, progress=progress)
    result.save(out)
    if not args.quiet:
        print(result.table())
        print(f"\ndesign saved to {out}")
    return 0


def _evaluate(args) -> int:
    from .config import load_workspace
    from .result import DesignResult

    result = DesignResult.load(args.design)
    if args.workspace is not None:
        workspace = load_workspace(args.workspace, result.problem.mechanism)
        result = DesignResult.load(args.design, mechanism=result.problem.mechanism, workspace=workspace)
    print(result.table())
    return 0


def _robots(args) -> int:
    from .robots import available_robots

    robots = available_robots()
    width = max((len(name) for name in robots), default=0)
    for name, path in robots.items():
        print(f"{name:<{width}s}  {path}" if args.paths else name)
    return 0


# ---------------------------------------------------------------------- helpers
def _check_output(out: Path) -> None:
    """Fail before solving when the design could not be saved at ``out``."""
    if out.is_dir():
        raise InputError(f"--out {str(out)!r} is a directory; give a file name such as design.json")
    folder = out.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise InputError(f"--out {str(out)!r}: {str(folder)!r} is not a directory")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"--out {str(out)!r}: folder {str(folder)!r} is not writable")


def _print_error(error) -> None:
    message = " ".join(str(error).split()) or type(error).__name__
    print(f"{PROG}: error: {message}", file=sys.stderr)


def _positive_int(text: str) -> int:
    value = _nonnegative_int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be ≥ 1, got {text!r}")
    return value


def _nonnegative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be ≥ 0, got {text!r}")
    return value


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
