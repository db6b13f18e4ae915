"""``springbalance payload-range DESIGN.json --body BODY``: the adjustable anchor against the payload [kg] at a
point of a body, and the largest payload balanced to a residual torque [N·m]."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from springbalance.errors import InputError
from springbalance.pipeline.payload import payload_range
from springbalance.results.payload import (
    PayloadRange,
    PayloadSweep,
    residual_vs_payload,
)
from springbalance.results.result import DesignResult


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``payload-range`` command to ``commands`` (with the options of ``common``)."""
    payload = commands.add_parser(
        "payload-range",
        parents=[common],
        help="anchor position against payload, and the largest payload, of a saved design",
        description="For a saved design with per-scenario variables (an adjustable anchor), keep the shared "
        "variables and re-fit the per-scenario ones for each payload MASS at POINT of BODY; print the "
        "table and the largest payload balanced to --max-residual. A design without per-scenario "
        "variables prints its residual torque against the payload instead.",
    )
    payload.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    payload.add_argument("--body", required=True, help="body (URDF link) that carries the payload")
    payload.add_argument(
        "--point",
        type=float,
        nargs=3,
        default=(0.0, 0.0, 0.0),
        metavar=("X", "Y", "Z"),
        help="payload position in the body frame [m] (default 0 0 0)",
    )
    payload.add_argument("--masses", type=float, nargs="+", metavar="M", help="payloads of the table [kg]")
    payload.add_argument(
        "--max-residual",
        type=float,
        metavar="R",
        help="peak residual torque [N·m] up to which a payload counts as balanced "
        "(default 1e-6 of the bare arm's peak gravity torque)",
    )
    payload.add_argument("--plot", metavar="PATH", help="also save the plot as PATH.png and PATH.svg")
    payload.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Print the payload table (and save its plot with ``--plot``)."""
    result = DesignResult.load(args.design)
    if args.body not in result.problem.mechanism.body_names:
        raise InputError(
            f"--body: unknown body {args.body!r}; bodies: {', '.join(result.problem.mechanism.body_names)}"
        )
    study: PayloadRange | PayloadSweep
    if result.problem.model.per_scenario:
        study = payload_range(result, args.body, args.point, max_residual=args.max_residual, masses=args.masses)
    else:
        masses = args.masses if args.masses else np.linspace(0.0, 2.0, 5)
        study = residual_vs_payload(result, args.body, masses, args.point)
    print(study.table())
    if args.plot:
        study.plot(args.plot)
        print(f"plot saved to {Path(args.plot).with_suffix('.png')} and .svg")
    return 0
