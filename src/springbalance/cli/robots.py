"""``springbalance robots``: the robot names of example-robot-data (``mechanism: {robot: NAME}``)."""

from __future__ import annotations

import argparse

from springbalance.model.robots import available_robots


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``robots`` command to ``commands`` (with the options of ``common``)."""
    robots = commands.add_parser(
        "robots",
        parents=[common],
        help="list the robots of example-robot-data",
        description="List the robot names accepted by 'mechanism: {robot: NAME}' in a config.",
    )
    robots.add_argument("--paths", action="store_true", help="also print the URDF file of each robot")
    robots.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Print one robot name a line (with ``--paths``, its URDF file next to it)."""
    robots = available_robots()
    width = max((len(name) for name in robots), default=0)
    for name, path in robots.items():
        print(f"{name:<{width}s}  {path}" if args.paths else name)
    return 0
