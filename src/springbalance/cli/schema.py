"""``springbalance schema``: the JSON Schema of config files, on stdout or in a file."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from springbalance.cli.inputs import check_output
from springbalance.files import write_text_atomic
from springbalance.io.schema import schema_text


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``schema`` command to ``commands`` (with the options of ``common``)."""
    schema = commands.add_parser(
        "schema",
        parents=[common],
        help="print the JSON Schema of config files",
        description="Print the JSON Schema (draft 2020-12) that config files follow, for editors (completion "
        "and checking, e.g. with a '# yaml-language-server: $schema=PATH' first line) and other "
        "validators; --out writes it to a file instead.",
    )
    schema.add_argument("--out", "-o", metavar="PATH", help="write the schema to PATH (atomically) instead of stdout")
    schema.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Print the schema, or write it atomically to ``--out``."""
    text = schema_text()
    if args.out is None:
        sys.stdout.write(text)
        return 0
    check_output(Path(args.out), example="config.schema.json")
    write_text_atomic(args.out, text)
    print(f"schema written to {args.out}")
    return 0
