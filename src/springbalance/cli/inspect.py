"""``springbalance inspect ROBOT_OR_URDF``: the bodies, joints, masses and ground of a robot or URDF (the names
a config's anchors and workspace use)."""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from springbalance.cli.formatting import PROG, mechanism_summary
from springbalance.errors import InputError
from springbalance.model.mechanism import Mechanism


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``inspect`` command to ``commands`` (with the options of ``common``)."""
    inspect = commands.add_parser(
        "inspect",
        parents=[common],
        help="list the bodies and joints of a robot or URDF (the names anchors and workspaces use)",
        description="Print the bodies (mass, centre of mass in the body frame, parent joint), the joints (type, "
        "axis, limits, mimic coupling), the total mass and the ground bodies of an example-robot-data "
        "robot or a URDF file: the names to write in a config's anchors and workspace.",
    )
    inspect.add_argument(
        "source",
        metavar="ROBOT_OR_URDF",
        help="a URDF file (an existing file, or any path with a '/' or ending in .urdf or .xml) "
        f"or an example-robot-data robot name (see '{PROG} robots')",
    )
    inspect.add_argument("--json", action="store_true", help="print the description as JSON instead of tables")
    inspect.add_argument(
        "--mimic",
        action="store_true",
        help="couple mimic joints to their primary joints (as 'mechanism: {mimic: true}' in a config)",
    )
    inspect.add_argument(
        "--no-validate",
        action="store_true",
        help="load a URDF whose masses, inertias or joint limits are physically impossible (as "
        "'mechanism: {validate: false}' in a config); malformed numbers are still refused",
    )
    inspect.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Print the mechanism's summary as tables, or as JSON with ``--json``."""
    summary = load_mechanism(args.source, mimic=args.mimic, validate=not args.no_validate).summary()
    print(json.dumps(summary, indent=2) if args.json else mechanism_summary(summary))
    return 0


def load_mechanism(argument: str, mimic: bool = False, validate: bool = True) -> Mechanism:
    """The URDF file ``argument`` if it is a file or looks like a path, else the robot of that name."""
    path = Path(argument)
    if path.is_file():
        return Mechanism.from_urdf(path, mimic=mimic, validate=validate)
    if "/" in argument or os.sep in argument or path.suffix.lower() in (".urdf", ".xml"):
        if path.is_dir():
            raise InputError(f"{argument!r} is a directory; give a URDF file or an example-robot-data robot name")
        return Mechanism.from_urdf(path, mimic=mimic, validate=validate)
    try:
        return Mechanism.from_robot(argument, mimic=mimic, validate=validate)
    except InputError as error:
        if path.is_dir():
            raise InputError(f"{argument!r} is a directory, not a URDF file, and {error}") from None
        raise
