"""``springbalance clearance DESIGN.json``: the smallest distance [m] of each spring of a saved design to the
arm's collision geometry over the workspace."""

from __future__ import annotations

import argparse

from springbalance.cli.arguments import positive_int
from springbalance.cli.outcome import FAILED_CHECK, OK
from springbalance.results.result import DesignResult


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``clearance`` command to ``commands`` (with the options of ``common``)."""
    clearance = commands.add_parser(
        "clearance",
        parents=[common],
        help="check that the springs of a saved design stay clear of the arm",
        description="Model each two-point spring of a saved design as a capsule between its end points and "
        "print its smallest distance to the URDF's collision geometry over the workspace, with the "
        "closest link and the pose. The collision objects of a spring's two anchor bodies are exempt. "
        "An independent check of the finished design, against the URDF's own shapes (a config's "
        "clearance section makes the optimisation keep the margin). Exits with 3 when a spring comes closer "
        "than the margin.",
    )
    clearance.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    clearance.add_argument(
        "--samples",
        "-n",
        type=positive_int,
        metavar="N",
        help="check N Sobol poses over the workspace's joint ranges instead of its own poses",
    )
    clearance.add_argument(
        "--radius",
        "-r",
        type=float,
        metavar="R",
        help="capsule radius [m] of springs without a helical spec sheet (default 0.01; a "
        "helical spring uses half its outer diameter)",
    )
    clearance.add_argument(
        "--margin",
        "-m",
        type=float,
        default=None,
        metavar="M",
        help="clearance asked for [m]; springs closer than this are flagged (default: the "
        "design's clearance.margin, else 0)",
    )
    clearance.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Print the clearance report: per spring the smallest distance [m], the closest link and the pose; 3 when a
    spring comes closer than the margin (or touches the arm)."""
    result = DesignResult.load(args.design)
    report = result.clearance(radius=args.radius, samples=args.samples, margin=args.margin)
    print("\n".join(report.lines()))
    return OK if report.clear else FAILED_CHECK
