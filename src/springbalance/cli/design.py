"""``springbalance design CONFIG --out DESIGN.json``: solve the design problem of a config file and save the
design (then, with ``--stock``, pick catalogue springs and re-optimise the anchors).

A design that fails a check (:meth:`~springbalance.results.result.DesignResult.failures`) is printed with
its report, one line per failure goes to stderr, nothing is saved unless ``--partial`` is given (then the
file is marked ``"partial": true``), and the exit status is 3 (:mod:`springbalance.cli.outcome`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from springbalance.cli.arguments import nonnegative_int, positive_int, seed_list
from springbalance.cli.formatting import PROG, interrupted_message
from springbalance.cli.inputs import check_output
from springbalance.cli.outcome import INTERRUPTED, failure_summary, outcome, print_failures
from springbalance.design.solvers import METHODS
from springbalance.design.stock import StockSelection
from springbalance.design.verification_loop import MODES as VERIFY_MODES
from springbalance.errors import Interrupted
from springbalance.files import write_json_atomic
from springbalance.io.config import load_config
from springbalance.io.stock_catalogues import load_stock
from springbalance.pipeline import solve
from springbalance.results.range_flags import beyond_joint_limits
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
        help="where to save the design (written only when the solve succeeds and the design passes every "
        "check; see --partial)",
    )
    design.add_argument(
        "--starts", type=positive_int, metavar="N", help="number of starts of the multi-start (overrides solve.starts)"
    )
    _add_seed_options(design)
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
        "--verify",
        choices=VERIFY_MODES,
        metavar="MODE",
        help="the check at 10x as many unseen poses: %(choices)s (overrides solve.verify; default resolve: "
        "re-solve with the worst poses added where a rule fails there)",
    )
    design.add_argument(
        "--stock",
        metavar="CATALOGUE",
        help="then pick each extension and compression spring from these stock parts and re-optimise the "
        "anchors: ms24585 (compression) and/or ms24586 (extension), the standard catalogues, or a CSV file "
        "(columns: docs/guides/coils-and-stock.md); several separated by commas (overrides solve.stock)",
    )
    design.add_argument("--quiet", "-q", action="store_true", help="print nothing on success, no progress bar")
    design.add_argument(
        "--partial",
        action="store_true",
        help='save a design that is not finished at --out, marked "partial": true: on Ctrl-C, the best '
        "design of the starts that had finished; a design that fails a check, with its failures (the "
        "exit status stays 3)",
    )
    design.set_defaults(handler=handle)


def _add_seed_options(design: argparse.ArgumentParser) -> None:
    """``--seed`` and ``--seeds``, one or the other."""
    seeds = design.add_mutually_exclusive_group()
    seeds.add_argument(
        "--seed", type=nonnegative_int, metavar="S", help="seed of the start points (overrides solve.seed and seeds)"
    )
    seeds.add_argument(
        "--seeds",
        type=seed_list,
        metavar="LIST",
        help="solve at each of these seeds (0-4, or 0,3,7) and keep the best design: the first that passes every "
        "check, by objective; the report lists what each seed gave (overrides solve.seed and seeds)",
    )


def handle(args: argparse.Namespace) -> int:
    """Solve, (pick stock springs,) print the report and save atomically; 3 (nothing saved without
    ``--partial``) when the design fails a check, 130 when Ctrl-C stops the solve."""
    out = Path(args.out)
    check_output(out)
    parts = None
    if args.stock is not None:  # a bad catalogue fails before the solve
        parts = load_stock(args.stock)
    config = load_config(args.config)
    catalogue = args.stock if args.stock is not None else config.stock_source
    for flag in beyond_joint_limits(config.problem.mechanism, config.problem.base_workspace.joint_values):
        print(f"{PROG}: warning: {flag.message}", file=sys.stderr)
    progress = False if args.quiet else None
    overrides = {
        "starts": args.starts,
        "seed": args.seed,
        "seeds": args.seeds,
        "method": args.method,
        "workers": args.workers,
        "verify": args.verify,
    }
    try:
        result = solve(config, **overrides, progress=progress, stock=parts)
    except Interrupted as stop:
        return _interrupted(stop, out, args.partial)
    failures = result.failures()
    if failures and args.partial:
        result.partial = failure_summary(failures)
    saved = not failures or args.partial
    if saved:
        _save_design(result, out, result.stock, catalogue)
    if not args.quiet:
        print(result.table())
        if result.stock is not None:
            print(f"\n{result.stock.summary()}")
        print(_saved_line(out, saved, bool(failures)))
    print_failures(
        failures,
        f"saved to {out} marked partial" if saved else f"nothing saved ({out} is unchanged; --partial saves it)",
        one_seed=result.seed_search is None,
    )
    return outcome(failures)


def _saved_line(out: Path, saved: bool, failed: bool) -> str:
    """The report's last line: where the design went."""
    if not saved:
        return f"\nthe design fails a check: not saved ({out} is unchanged; --partial saves it)"
    return f"\ndesign saved to {out}" + (" (partial: it fails the checks listed above)" if failed else "")


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
            partial=f"interrupted: {stop}",
        )
        _save_design(result, out)
    print(interrupted_message(stop, out, partial), file=sys.stderr)
    return INTERRUPTED


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
