"""The argument parser of ``springbalance``: the global options, then one sub-command per module of
:mod:`springbalance.cli`, each adding its own parser (``add_parser``) with its handler."""

from __future__ import annotations

import argparse

from springbalance._version import __version__
from springbalance.cli import (
    clearance,
    design,
    evaluate,
    explore,
    export,
    inspect,
    order,
    payload_range,
    report,
    robots,
    schema,
    view,
)
from springbalance.cli.arguments import MEMORY_HELP
from springbalance.cli.formatting import PROG

#: the commands in the order ``springbalance --help`` lists them
COMMANDS = (design, evaluate, clearance, view, report, order, export, payload_range, robots, inspect, explore, schema)


def build_parser() -> argparse.ArgumentParser:
    """The parser of the whole command line; each command's parser sets ``handler``, its function
    ``(args) -> exit status``."""
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Design gravity-balancing springs for robot arms described by URDF.",
        epilog="Exit status: 0 success, 1 solver found no feasible design, 2 bad input. "
        f"Run '{PROG} COMMAND --help' for the options of a command.",
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    parser.add_argument("--max-memory", metavar="SIZE", help=MEMORY_HELP)
    # also accepted after the command's name (the command's value wins)
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--max-memory", metavar="SIZE", default=argparse.SUPPRESS, help=MEMORY_HELP)
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for command in COMMANDS:
        command.add_parser(commands, common)
    return parser
