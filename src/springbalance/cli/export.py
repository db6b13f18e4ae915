"""``springbalance export DESIGN.json --urdf OUT.urdf --mjcf OUT.xml``: the balanced arm as a URDF with spring
anchors and/or a MuJoCo model."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from springbalance.cli.formatting import PROG
from springbalance.cli.inputs import check_output
from springbalance.errors import InputError
from springbalance.export.common import law_warnings
from springbalance.export.mjcf import mjcf_string
from springbalance.export.urdf import sidecar_path, urdf_strings
from springbalance.files import write_text_atomic
from springbalance.results.result import DesignResult


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``export`` command to ``commands`` (with the options of ``common``)."""
    export = commands.add_parser(
        "export",
        parents=[common],
        help="write the balanced arm as a URDF with spring anchors and/or a MuJoCo model",
        description="Write the design's URDF with a massless link at every spring anchor and the spring "
        "records (plus a .springs.json sidecar), and/or a MuJoCo model (MJCF) with a tendon per "
        "spring. Springs whose real law MuJoCo's linear two-sided spring cannot express at some "
        "workspace sample are listed as warnings; files are written atomically.",
    )
    export.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    export.add_argument("--urdf", metavar="OUT.urdf", help="URDF to write (with OUT.springs.json next to it)")
    export.add_argument("--mjcf", metavar="OUT.xml", help="MuJoCo model to write")
    export.add_argument(
        "--resolve-packages", action="store_true", help="replace package:// mesh paths of the URDF by absolute paths"
    )
    export.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Build every file's text (and check it) first, then write them atomically; print the law warnings."""
    if args.urdf is None and args.mjcf is None:
        raise InputError("export: give --urdf OUT.urdf and/or --mjcf OUT.xml")
    for option, value, example in (("--urdf", args.urdf, "balanced.urdf"), ("--mjcf", args.mjcf, "balanced.xml")):
        if value is not None:
            check_output(Path(value), option, example)
    result = DesignResult.load(args.design)
    # both texts are built (and checked) before anything is written: a failure leaves no file
    files, warnings = {}, law_warnings(result)
    if args.urdf is not None:
        urdf, sidecar = urdf_strings(result, Path(args.urdf).name, resolve_packages=args.resolve_packages)
        files.update({Path(args.urdf): urdf, sidecar_path(args.urdf): sidecar})
    if args.mjcf is not None:
        mjcf, mjcf_warnings = mjcf_string(result)
        files[Path(args.mjcf)] = mjcf
        warnings += [warning for warning in mjcf_warnings if warning not in warnings]
    for path, text in files.items():
        write_text_atomic(path, text)
    print(f"wrote {', '.join(str(path) for path in files)}")
    for warning in warnings:
        print(f"{PROG}: warning: {warning}", file=sys.stderr)
    return 0
