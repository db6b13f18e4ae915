"""``springbalance evaluate DESIGN.json``: print the report of a saved design, on its own workspace or another."""

from __future__ import annotations

import argparse

from springbalance.cli.inputs import load_result
from springbalance.cli.outcome import outcome, print_failures


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``evaluate`` command to ``commands`` (with the options of ``common``)."""
    evaluate = commands.add_parser(
        "evaluate",
        parents=[common],
        help="print the report of a saved design",
        description="Load a design saved by 'springbalance design' and print its report, on the "
        "workspace it was designed on or on another one. Exits with 3 when the design fails a check "
        "(or was saved with --partial).",
    )
    evaluate.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    evaluate.add_argument(
        "--workspace",
        "-w",
        metavar="WORKSPACE.yaml",
        help="YAML/JSON file with a 'workspace:' mapping (a whole config works too) "
        "to evaluate the design on instead of its own workspace",
    )
    evaluate.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Print the design's table (variables, springs, residual torque [N·m], metrics, findings); 3, with one
    line per failure on stderr, when the design fails a check or was saved partial."""
    result = load_result(args.design, args.workspace)
    print(result.table())
    failures = result.failures()
    print_failures(failures)
    return outcome(failures)
