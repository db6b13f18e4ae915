"""``springbalance export DESIGN.json --urdf OUT.urdf --mjcf OUT.xml``: the balanced arm as a URDF with spring
anchors and/or a MuJoCo model.

A design that fails a check (:meth:`~springbalance.results.result.DesignResult.failures`, a file saved with
``--partial`` included) is not a part to build: one line per failure goes to stderr, nothing is written
unless ``--partial`` is given (then each file is marked: an XML comment at the top of the URDF and the MJCF,
``"partial": true`` and ``"partial_reason"`` in the sidecar), and the exit status is 3, as for ``design``
(:mod:`springbalance.cli.outcome`).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from springbalance.cli.formatting import PROG
from springbalance.cli.inputs import check_output
from springbalance.cli.outcome import failure_summary, outcome, print_failures
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
        "workspace sample are listed as warnings; files are written atomically. A design that fails a check "
        "is not exported (exit status 3) unless --partial is given.",
    )
    export.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    export.add_argument("--urdf", metavar="OUT.urdf", help="URDF to write (with OUT.springs.json next to it)")
    export.add_argument("--mjcf", metavar="OUT.xml", help="MuJoCo model to write")
    export.add_argument(
        "--resolve-packages", action="store_true", help="replace package:// mesh paths of the URDF by absolute paths"
    )
    export.add_argument(
        "--partial",
        action="store_true",
        help="export a design that fails a check all the same, each file marked partial (the exit status stays 3)",
    )
    export.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Build every file's text (and check it) first, then write them atomically; print the law warnings.
    A design that fails a check: nothing written (exit status 3), or with ``--partial`` every file marked."""
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
    failures = result.failures()
    written = not failures or args.partial
    if written:
        marked = {path: _marked(text, failure_summary(failures)) if failures else text for path, text in files.items()}
        for path, text in marked.items():
            write_text_atomic(path, text)
        print(f"wrote {', '.join(str(path) for path in files)}" + (" (marked partial)" if failures else ""))
    for warning in warnings:
        print(f"{PROG}: warning: {warning}", file=sys.stderr)
    print_failures(
        failures,
        "written marked partial: not a part to build"
        if written
        else "nothing written (existing files are unchanged; --partial writes them, marked partial)",
    )
    return outcome(failures)


def _marked(text: str, reason: str) -> str:
    """``text`` (a URDF or MJCF, or the sidecar's JSON) marked as the export of a partial design: an XML comment
    after the declaration, or ``"partial": true`` and ``"partial_reason"`` in the JSON record."""
    if text.lstrip().startswith("{"):
        return json.dumps({**json.loads(text), "partial": True, "partial_reason": reason}, indent=1) + "\n"
    comment = f"<!-- springbalance: PARTIAL design, not to be built: {reason.replace('--', '- -')} -->\n"
    if text.startswith("<?xml"):
        declaration, _, rest = text.partition("?>")
        return f"{declaration}?>\n{comment}{rest.lstrip()}"
    return comment + text
