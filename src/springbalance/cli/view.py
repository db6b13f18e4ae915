"""``springbalance view DESIGN.json``: serve the 3-D scene of a saved design in Meshcat on 127.0.0.1.

A design that fails a check is shown all the same (the scene shows what failed), as ``report`` writes its
report: one ``springbalance: failure:`` line per failure on stderr when the scene is served, and exit status 3
when the viewer is stopped (:mod:`springbalance.cli.outcome`)."""

from __future__ import annotations

import argparse
import time
import webbrowser

from springbalance.cli.arguments import port, positive_int
from springbalance.cli.formatting import PROG
from springbalance.cli.inputs import check_scene_budget
from springbalance.cli.outcome import outcome, print_failures
from springbalance.errors import SpringBalanceError
from springbalance.results.result import DesignResult
from springbalance.viz.design_scene import DesignScene
from springbalance.viz.live import MeshcatServer, publish_scene


def add_parser(commands: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """Add the ``view`` command to ``commands`` (with the options of ``common``)."""
    view = commands.add_parser(
        "view",
        parents=[common],
        help="show a saved design in Meshcat, served on 127.0.0.1",
        description="Serve the 3-D scene of a saved design on this machine only (127.0.0.1): the arm, each "
        "spring as a helix coloured by its tension, animated through a sweep of each joint, with a pose slider "
        "that shows each spring's force and each joint's residual torque at the pose. "
        "Prints the URL and serves until Ctrl-C. Exits with 3 when the design fails a check (one line per "
        "failure on stderr when the scene is served).",
    )
    view.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    view.add_argument("--port", type=port, metavar="P", help="web port (default: the first free one from 7000)")
    view.add_argument("--open", action="store_true", help="also open the URL in the default web browser")
    view.add_argument(
        "--frames", type=positive_int, default=48, metavar="N", help="animation frames per swept joint (default 48)"
    )
    view.add_argument(
        "--poses",
        default="sweep",
        metavar="WHICH",
        help="the poses the scene animates and its pose slider scrubs: sweep (each joint in turn, default), "
        "workspace (the design's samples) or worst[:N] (its N worst samples, worst first; default 12)",
    )
    view.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    """Draw the scene, print its URL and serve it until Ctrl-C: exit status 0, or 3 (with one line per failure on
    stderr when the scene is served) when the design fails a check."""
    result = DesignResult.load(args.design)
    failures = result.failures()
    check_scene_budget(result, args.frames, args.poses)
    scene = DesignScene(result, frames_per_joint=args.frames, poses=args.poses)
    server = MeshcatServer(port=args.port)
    try:
        scene.draw(server.visualizer())
        page = publish_scene(server, scene)
        print(
            f"{PROG}: the scene of {args.design} is at {page} (with its pose slider; meshcat's own viewer: {server.web_url})"
        )
        print(f"  {scene.color_scale.describe()}")
        if scene.skipped:
            print(f"  not drawn (they act in a joint): {', '.join(scene.skipped)}")
        print_failures(failures, "shown all the same: not a part to build (exit status 3)")
        print("  press Ctrl-C to stop", flush=True)
        if args.open:
            webbrowser.open(page, new=2)
        while server.running:
            time.sleep(0.25)
        raise SpringBalanceError("the meshcat server stopped unexpectedly")
    except KeyboardInterrupt:
        print(f"{PROG}: stopped", flush=True)
        return outcome(failures)
    finally:
        server.stop()
