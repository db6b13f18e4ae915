"""``springbalance report DESIGN.json --out FOLDER``: the HTML report of a saved design (tables, plots,
3-D scene)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from springbalance.cli.arguments import positive_int
from springbalance.cli.inputs import check_scene_budget, load_result
from springbalance.cli.outcome import outcome, print_failures
from springbalance.errors import InputError


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``report`` command to ``commands`` (with the options of ``common``)."""
    report = commands.add_parser(
        "report",
        parents=[common],
        help="write an HTML report of a saved design (tables, plots, 3-D scene)",
        description="Write FOLDER/report.html (design and metrics tables, plots), FOLDER/scene.html (the "
        "self-contained Meshcat scene, opens without a server or network), FOLDER/torques.png/.svg "
        "and FOLDER/histogram.png/.svg. Exits with 3 when the design fails a check (the report says which).",
    )
    report.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    report.add_argument("--out", "-o", required=True, metavar="FOLDER", help="folder for the report (created)")
    report.add_argument(
        "--workspace", "-w", metavar="WORKSPACE.yaml", help="report on another workspace (as for 'evaluate')"
    )
    report.add_argument("--no-scene", action="store_true", help="leave out scene.html")
    report.add_argument(
        "--frames",
        type=positive_int,
        default=48,
        metavar="N",
        help="animation frames per swept joint in scene.html (default 48)",
    )
    report.add_argument(
        "--poses",
        default="sweep",
        metavar="WHICH",
        help="the poses the scene animates and its pose slider scrubs: sweep (each joint in turn, default), "
        "workspace (the design's samples) or worst[:N] (its N worst samples, worst first; default 12)",
    )
    report.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Write the report's files into ``--out`` and list them; 3, with one line per failure on stderr, when
    the design fails a check (its report says which, and is written all the same: it shows what failed)."""
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {str(out)!r} is a file; give a folder")
    result = load_result(args.design, args.workspace)
    if not args.no_scene:
        check_scene_budget(result, args.frames, args.poses)
    started = time.time()
    path = result.report(out, scene=not args.no_scene, frames_per_joint=args.frames, poses=args.poses)
    # the files this report wrote (the plots depend on the design: coils, tolerances), report.html first
    written = [item.name for item in sorted(out.iterdir()) if item.is_file() and item.stat().st_mtime >= started - 1]
    files = sorted(written, key=lambda name: (name != "report.html", name != "scene.html", name))
    print(f"report written to {path}")
    print(f"  files in {out}: {', '.join(files)}")
    failures = result.failures()
    print_failures(failures)
    return outcome(failures)
