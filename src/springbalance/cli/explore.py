"""``springbalance explore CONFIG --out FOLDER``: solve every spring topology of a study config on Dask and
report where springs should go."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from springbalance.cli.arguments import positive_int
from springbalance.errors import InputError
from springbalance.explore.execution import make_client
from springbalance.explore.pseudo_base_proposals import proposal_lines
from springbalance.explore.screening import faced
from springbalance.explore.study import Study, StudyResult, load_study


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``explore`` command to ``commands`` (with the options of ``common``)."""
    explore = commands.add_parser(
        "explore",
        parents=[common],
        help="find where springs should go: solve every spring topology on Dask (spatial arms: the fewest springs)",
        description="Enumerate the spring topologies of a study config (a design config with an 'explore' "
        "section instead of 'springs'), prune those that cannot balance exactly, solve the rest as "
        "tasks on a Dask cluster (a local one with a worker process per core by default), and write "
        "each result as it finishes into OUT/results/, then OUT/results.csv, OUT/report.html and "
        "the best design per spring count (OUT/best_<k>_springs.json). Running it again resumes. On an arm of "
        "revolute joints with zero-free-length springs it searches for the fewest springs instead: each count's "
        "unproven topologies are screened on the exact coefficients (explore.screen draws each), and only what the "
        "screen finds is solved.",
    )
    explore.add_argument("config", metavar="CONFIG", help="study config file (.yaml, .yml or .json)")
    explore.add_argument("--out", "-o", required=True, metavar="FOLDER", help="the study folder")
    explore.add_argument(
        "--max-springs",
        type=int,
        metavar="N",
        help="most springs per topology (overrides explore.max_springs; default 2)",
    )
    explore.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on an existing Dask cluster (e.g. tcp://host:8786) instead of a local one",
    )
    explore.add_argument(
        "--workers",
        type=positive_int,
        metavar="W",
        help="worker processes of the local cluster (default: one per core)",
    )
    explore.add_argument(
        "--timeout",
        type=float,
        default=10.0,
        metavar="SECONDS",
        help="how long to wait for the scheduler given by --scheduler (default 10)",
    )
    explore.add_argument(
        "--sequential", action="store_true", help="solve the tasks one after another in this process (no Dask)"
    )
    explore.add_argument(
        "--force",
        action="store_true",
        help="use a study folder that holds another study's results (they are discarded)",
    )
    explore.add_argument("--quiet", "-q", action="store_true", help="no progress bar and no summary")
    explore.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Run (or resume) the study on a Dask client (none with ``--sequential`` or nothing left to solve), then
    print its summary."""
    if args.max_springs is not None and args.max_springs < 1:
        raise InputError(f"--max-springs must be an integer ≥ 1, got {args.max_springs}")
    if args.sequential and (args.scheduler or args.workers):
        raise InputError("--sequential runs without Dask: it takes no --scheduler or --workers")
    study = load_study(args.config, max_springs=args.max_springs)
    if not args.quiet:  # the size of the study before anything is solved, per spring count
        summary = study.summary()
        then = (
            "fewest-springs search: each count screened on the exact coefficients, from 1 spring up to the first "
            "exact design"
            if study.search is not None
            else f"{study.pending(args.out)} task(s) to solve"
        )
        print(
            f"{len(study.candidates)} candidates, {summary['topologies']} topologies × {summary['grid_points']} grid "
            f"point(s), {len(summary['unreachable'])} proven unreachable: {then}",
            *faced(study.topologies, study.verdicts),
            sep="\n",
            flush=True,
        )
    # nothing left to solve (a finished study run again): no cluster to start
    client = (
        None
        if args.sequential or not study.pending(args.out)
        else make_client(args.scheduler, args.workers, args.timeout)
    )
    try:
        result = study.run(args.out, client=client, force=args.force, progress=not args.quiet)
    finally:
        if client is not None:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None and args.scheduler is None:
                cluster.close()
    if not args.quiet:
        _print_summary(study, result, Path(args.out))
    return 0


def _print_summary(study: Study, result: StudyResult, out: Path) -> None:
    """The counts of the study (candidates, topologies, pruned, dominated, solved) and its best design per
    spring count (residual as a fraction of the unbalanced peak torque)."""
    summary = study.summary()
    print(
        f"{len(study.candidates)} candidates, {summary['topologies']} topologies × {summary['grid_points']} "
        f"grid point(s); {summary['reachability']}: {len(summary['unreachable'])} proven unreachable, "
        f"{len(summary['degenerate'])} degenerate; {len(result.dominated)} dominated; solved "
        f"{len(result.solved)} now, {result.resumed} from an earlier run"
    )
    for screened in study.search.counts.values() if study.search is not None else []:
        print(f"  screened {screened.describe()} ({screened.seconds:.1f} s)")
    for count, record in result.best().items():
        print(
            f"  best with {count} spring(s): {' + '.join(record['springs'])}  residual "
            f"{record['relative_residual']:.3g} of the unbalanced peak{'  (exact)' if record['exact'] else ''}"
            f"{_how(record)}"
            f"{'  FAILS: ' + ', '.join(record['failures']) if record.get('ok') is False else ''}"
            f"  -> {out / f'best_{count}_springs.json'}"
        )
    for proposal in proposal_lines(
        json.loads((out / "study.json").read_text(encoding="utf-8")).get("pseudo_base_proposals", [])
    ):
        print(proposal)
    print(f"report: {out / 'report.html'}")


def _how(record: dict) -> str:
    """How a count's best design was found, when not solved for exact balance: the best screened topology (the
    fewest-springs search found none exact), or the best of the pruned few."""
    if not record.get("pruned"):
        return ""
    if record["pruned"].startswith("screened"):
        return "  (approximate: the best screened topology; none of this count found exact)"
    return "  (approximate: every topology of this count was pruned)"
