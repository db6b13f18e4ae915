"""``springbalance order DESIGN.json --out FOLDER``: what a spring maker needs to quote the design's springs
(the DIN 2099 form's fields as a page and JSON, a drawing per spring, the bill of materials).

A design that fails a check writes nothing and exits with 3 unless ``--partial`` is given (then the order is
written, marked on every page as the order of a failing design, and the exit status stays 3). A design
without a helical spring has nothing to quote: one line says so and the exit status is 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from springbalance.cli.arguments import positive_int
from springbalance.cli.formatting import PROG
from springbalance.cli.inputs import load_result
from springbalance.cli.outcome import outcome, print_failures
from springbalance.errors import InputError
from springbalance.files import write_text_atomic
from springbalance.results.order.form import OrderOptions
from springbalance.results.order.page import order_files
from springbalance.results.order.tolerances import DEFAULT_GRADE, GRADES

#: the files listed first, in this order
MAIN_FILES = ("order.html", "order.json", "bom.csv")


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``order`` command to ``commands`` (with the options of ``common``)."""
    order = commands.add_parser(
        "order",
        parents=[common],
        help="write the order of a saved design's springs (DIN 2099 form, drawings, bill of materials)",
        description="Write FOLDER/order.html (per helical spring the fields of the DIN 2099 form a spring maker "
        "quotes from, with its drawing), FOLDER/order.json (the same record), FOLDER/<spring>.svg (the "
        "dimensioned drawing of each spring) and FOLDER/bom.csv (springs, anchors, cables and pulleys). "
        "Exits with 3 and writes nothing when the design fails a check (unless --partial), with 2 when it "
        "has no helical spring (nothing to quote).",
    )
    order.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    order.add_argument("--out", "-o", required=True, metavar="FOLDER", help="folder for the order (created)")
    order.add_argument(
        "--workspace", "-w", metavar="WORKSPACE.yaml", help="take the working extremes over another workspace"
    )
    order.add_argument(
        "--grade",
        type=int,
        choices=GRADES,
        default=DEFAULT_GRADE,
        help="quality grade of DIN 2097 (extension) and EN 15800 (compression springs) (default %(default)s)",
    )
    order.add_argument(
        "--finish", metavar="TEXT", help="the surface finish to order (e.g. 'oiled'); default: none named"
    )
    order.add_argument(
        "--direction",
        choices=("right-hand", "left-hand"),
        default="right-hand",
        help="coil direction (default %(default)s)",
    )
    order.add_argument("--quantity", type=positive_int, default=1, metavar="N", help="sets of springs (default 1)")
    order.add_argument(
        "--partial",
        action="store_true",
        help="write the order of a design that fails a check, marked as such (the exit status stays 3)",
    )
    order.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Render the order, then write it (each file atomically) unless the design fails a check and
    ``--partial`` is not given; 3 when it fails a check, 2 (InputError) when there is nothing to quote."""
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {str(out)!r} is a file; give a folder")
    result = load_result(args.design, args.workspace)
    failures = result.failures()
    if failures and args.partial and not result.partial:
        result.partial = f"it fails {len(failures)} check(s): {', '.join(sorted({f.kind for f in failures}))}"
    options = OrderOptions(grade=args.grade, finish=args.finish, direction=args.direction, quantity=args.quantity)
    files = order_files(result, options, design=str(args.design))  # InputError when there is nothing to quote
    written = not failures or args.partial
    if written:
        names = [name for name in MAIN_FILES if name in files] + sorted(set(files) - set(MAIN_FILES))
        for name in names:
            write_text_atomic(out / name, files[name])
        print(f"order written to {out / 'order.html'}")
        print(f"  files in {out}: {', '.join(names)}")
    print_failures(failures)
    if failures:
        print(
            f"{PROG}: the design fails {len(failures)} check(s); "
            + ("the order is marked partial" if written else "nothing written (--partial writes it)"),
            file=sys.stderr,
        )
    return outcome(failures)
