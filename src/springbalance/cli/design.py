"""``springbalance design CONFIG --out DESIGN.json``: solve the design problem of a config file and save the
design (then, with ``--stock``, pick catalogue springs and re-optimise the anchors)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from springbalance.cli.arguments import nonnegative_int, positive_int
from springbalance.cli.formatting import interrupted_message
from springbalance.cli.inputs import check_output
from springbalance.design.solvers import METHODS
from springbalance.design.stock import StockSelection
from springbalance.errors import Interrupted
from springbalance.files import write_json_atomic
from springbalance.io.catalogue import read_catalogue
from springbalance.io.config import load_config
from springbalance.pipeline import solve
from springbalance.results.result import DesignResult


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``design`` command to ``commands`` (with the options of ``common``)."""
    design = commands.add_parser(
        "design",
        parents=[common],
        help="solve the design problem of a config file and save the design",
        description="Build the design problem described by CONFIG (YAML or JSON), solve it with a "
        "multi-start, print the report and save the design as JSON.",
    )
    design.add_argument("config", metavar="CONFIG", help="config file (.yaml, .yml or .json)")
    design.add_argument(
        "--out",
        "-o",
        required=True,
        metavar="DESIGN.json",
        help="where to save the design (written only when the solve succeeds)",
    )
    design.add_argument(
        "--starts", type=positive_int, metavar="N", help="number of starts of the multi-start (overrides solve.starts)"
    )
    design.add_argument(
        "--seed", type=nonnegative_int, metavar="S", help="seed of the start points (overrides solve.seed)"
    )
    design.add_argument(
        "--method",
        choices=METHODS,
        metavar="METHOD",  # a metavar: argparse lists no choices up front
        help="solver backend: %(choices)s (overrides solve.method)",
    )
    design.add_argument(
        "--workers",
        type=positive_int,
        metavar="W",
        help="processes that run the starts at once (overrides solve.workers; default: the "
        "number of cores); the design does not depend on it",
    )
    design.add_argument(
        "--stock",
        metavar="CATALOGUE.csv",
        help="then pick each extension and compression spring from this stock catalogue (CSV, "
        "columns: docs/guides/coils-and-stock.md) and re-optimise the anchors",
    )
    design.add_argument("--quiet", "-q", action="store_true", help="print nothing on success, no progress bar")
    design.add_argument(
        "--partial",
        action="store_true",
        help="on Ctrl-C, save the best design of the starts that had finished at --out",
    )
    design.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Solve, (pick stock springs,) save atomically and print the report; 130 when Ctrl-C stops the solve."""
    out = Path(args.out)
    check_output(out)
    parts = None
    if args.stock is not None:  # a bad catalogue fails before the solve
        parts = read_catalogue(args.stock)
    config = load_config(args.config)
    progress = False if args.quiet else None
    overrides = {"starts": args.starts, "seed": args.seed, "method": args.method, "workers": args.workers}
    try:
        result = solve(config, **overrides, progress=progress, stock=parts)
    except Interrupted as stop:
        return _interrupted(stop, out, args.partial)
    selection = result.stock
    _save_design(result, out, selection, args.stock)
    if not args.quiet:
        print(result.table())
        if selection is not None:
            print(f"\n{selection.summary()}")
        print(f"\ndesign saved to {out}")
    return 0


def _interrupted(stop: Interrupted, out: Path, partial: bool) -> int:
    """Ctrl-C during ``design``: say which starts had finished; with ``--partial`` save the best so far."""
    if partial and stop.best_x is not None:
        result = DesignResult(
            stop.problem,
            stop.best_x,
            starts=stop.starts,
            method="interrupted",
            seed=None,
            status=f"{stop} (the best design so far, saved with --partial)",
        )
        _save_design(result, out)
    print(interrupted_message(stop, out, partial), file=sys.stderr)
    return 130


def _save_design(
    result: DesignResult, out: Path, selection: StockSelection | None = None, catalogue: str | None = None
) -> None:
    """Save ``result`` at ``out`` (atomically); a stock spring's ``part_number`` also goes into its
    ``design`` entry, and a stock selection into ``stock`` (catalogue, objective before/after, choices)."""
    record = result.to_dict()
    for entry, spring in zip(record.get("design", []), result.problem.springs):
        if getattr(spring, "part_number", None) is not None:
            entry.setdefault("part_number", spring.part_number)
    if selection is not None:
        record["stock"] = {"catalogue": str(catalogue), **selection.to_dict()}
    write_json_atomic(out, record)
