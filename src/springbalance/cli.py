"""The ``springbalance`` command-line tool.

::

    springbalance design CONFIG.yaml --out design.json [--starts N] [--seed S] [--method M] [--workers W] [--stock CATALOGUE.csv] [--quiet]
    springbalance evaluate design.json [--workspace WORKSPACE.yaml]
    springbalance clearance design.json [--samples N] [--radius R] [--margin M]
    springbalance view design.json [--port P] [--open] [--frames N]
    springbalance report design.json --out FOLDER [--no-scene]
    springbalance export design.json [--urdf OUT.urdf] [--mjcf OUT.xml] [--resolve-packages]
    springbalance payload-range design.json --body BODY [--point X Y Z] [--masses M ...] [--max-residual R] [--plot PATH]
    springbalance robots [--paths]
    springbalance inspect ROBOT_OR_URDF [--json] [--mimic]
    springbalance schema [--out config.schema.json]

Every command takes ``--max-memory SIZE`` (e.g. ``2G``; default: the environment variable
``SPRINGBALANCE_MAX_MEMORY``, else half the available memory): work whose estimated memory is
larger (a workspace of too many samples, a scene of too many frames) is refused before it starts
(:mod:`springbalance.model.budget`).

Exit status: 0 on success, 1 when the solver finds no feasible design, 2 on bad input
(unknown key, body or joint, malformed file, missing file, too little memory, ...). Errors are printed as one
line, ``springbalance: error: <message>``, on stderr, without a traceback; ``design``
writes its output file atomically and only after a successful solve, so a failed run
leaves no (partial) output file behind.
"""

from __future__ import annotations

import argparse
import atexit
import os
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path

from springbalance._version import __version__
from springbalance.errors import InputError, Interrupted, SolverError, SpringBalanceError

PROG = "springbalance"


def main(argv: list[str] | None = None) -> int:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    with warnings.catch_warnings():
        warnings.showwarning = _print_warning  # one line per warning, like the errors
        return _run(args)


def run() -> None:
    """The console script ``springbalance``: :func:`main`, then exit at once.

    The interpreter's own exit frees every object of the heap one by one (CasADi's and Pinocchio's
    objects, SciPy's modules: 0.1-0.2 s after a design) for memory that the operating system takes
    back anyway, so, as mypy does, the process ends with ``os._exit`` once the output is flushed and
    the exit handlers (``atexit``: a live viewer's server) have run. Every file was closed by the
    command itself (``design`` writes its output atomically), and no thread is left at work: the
    threads still alive (idle workers of a thread pool) end with the process."""
    status = main()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:   # output piped into e.g. `head`, which stopped reading
        status = 141
    atexit._run_exitfuncs()   # CPython's: the handlers a normal exit runs, in the same order
    os._exit(status)


def _run(args) -> int:
    from springbalance.model.budget import current_limit, memory_limit

    try:
        with memory_limit(getattr(args, "max_memory", None)):
            current_limit()  # a malformed SPRINGBALANCE_MAX_MEMORY is reported before any work
            return args.handler(args)
    except SolverError as error:
        _print_error(error)
        return 1
    except SpringBalanceError as error:
        _print_error(error)
        return 2
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so that flushing stdout at exit does not fail again
        return 141
    except OSError as error:  # file system trouble while reading or writing (e.g. disk full, permissions)
        detail = f"{error.strerror}: {error.filename!r}" if error.strerror and error.filename else error
        _print_error(detail)
        return 2
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except MemoryError:  # an allocation the estimates did not foresee
        _print_error("out of memory; lower the sample counts or set a lower --max-memory so that springbalance "
                     "refuses such work up front")
        return 2


def _print_warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"{PROG}: warning: {' '.join(str(message).split())}", file=sys.stderr)


class _Methods(Sequence):
    """The solver methods (:data:`springbalance.design.solvers.METHODS`) as the choices of ``--method``,
    imported when argparse checks or shows them: the commands that solve nothing (``--help``,
    ``inspect``, ``robots`` ...) do not load the solvers (casadi)."""

    def _methods(self) -> tuple[str, ...]:
        from springbalance.design.solvers import METHODS

        return METHODS

    def __getitem__(self, index):
        return self._methods()[index]

    def __len__(self) -> int:
        return len(self._methods())


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Design gravity-balancing springs for robot arms described by URDF.",
        epilog="Exit status: 0 success, 1 solver found no feasible design, 2 bad input. "
               f"Run '{PROG} COMMAND --help' for the options of a command.")
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    memory_help = ("refuse work estimated to need more memory than SIZE (e.g. 2G, 512M, or 'unlimited'; default: "
                   "the environment variable SPRINGBALANCE_MAX_MEMORY, else half the available memory)")
    parser.add_argument("--max-memory", metavar="SIZE", help=memory_help)
    # also accepted after the command's name (the command's value wins)
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--max-memory", metavar="SIZE", default=argparse.SUPPRESS, help=memory_help)
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    design = commands.add_parser(
        "design", parents=[common], help="solve the design problem of a config file and save the design",
        description="Build the design problem described by CONFIG (YAML or JSON), solve it with a "
                    "multi-start, print the report and save the design as JSON.")
    design.add_argument("config", metavar="CONFIG", help="config file (.yaml, .yml or .json)")
    design.add_argument("--out", "-o", required=True, metavar="DESIGN.json",
                        help="where to save the design (written only when the solve succeeds)")
    design.add_argument("--starts", type=_positive_int, metavar="N",
                        help="number of starts of the multi-start (overrides solve.starts)")
    design.add_argument("--seed", type=_nonnegative_int, metavar="S",
                        help="seed of the start points (overrides solve.seed)")
    design.add_argument("--method", choices=_Methods(), metavar="METHOD",  # a metavar: argparse lists no choices up front
                        help="solver backend: %(choices)s (overrides solve.method)")
    design.add_argument("--workers", type=_positive_int, metavar="W",
                        help="processes that run the starts at once (overrides solve.workers; default: the "
                             "number of cores); the design does not depend on it")
    design.add_argument("--stock", metavar="CATALOGUE.csv",
                        help="then pick each extension and compression spring from this stock catalogue (CSV, "
                             "columns in README 'Stock springs') and re-optimise the anchors")
    design.add_argument("--quiet", "-q", action="store_true", help="print nothing on success, no progress bar")
    design.add_argument("--partial", action="store_true",
                        help="on Ctrl-C, save the best design of the starts that had finished at --out")
    design.set_defaults(handler=_design)

    evaluate = commands.add_parser(
        "evaluate", parents=[common], help="print the report of a saved design",
        description="Load a design saved by 'springbalance design' and print its report, on the "
                    "workspace it was designed on or on another one.")
    evaluate.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    evaluate.add_argument("--workspace", "-w", metavar="WORKSPACE.yaml",
                          help="YAML/JSON file with a 'workspace:' mapping (a whole config works too) "
                               "to evaluate the design on instead of its own workspace")
    evaluate.set_defaults(handler=_evaluate)

    clearance = commands.add_parser(
        "clearance", parents=[common], help="check that the springs of a saved design stay clear of the arm",
        description="Model each two-point spring of a saved design as a capsule between its end points and "
                    "print its smallest distance to the URDF's collision geometry over the workspace, with the "
                    "closest link and the pose. The collision objects of a spring's two anchor bodies are exempt. "
                    "An independent check of the finished design, against the URDF's own shapes (a config's "
                    "clearance section makes the optimisation keep the margin).")
    clearance.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    clearance.add_argument("--samples", "-n", type=_positive_int, metavar="N",
                           help="check N Sobol poses over the workspace's joint ranges instead of its own poses")
    clearance.add_argument("--radius", "-r", type=float, metavar="R",
                           help="capsule radius [m] of springs without a helical spec sheet (default 0.01; a "
                                "helical spring uses half its outer diameter)")
    clearance.add_argument("--margin", "-m", type=float, default=None, metavar="M",
                           help="clearance asked for [m]; springs closer than this are flagged (default: the "
                                "design's clearance.margin, else 0)")
    clearance.set_defaults(handler=_clearance)

    view = commands.add_parser(
        "view", parents=[common], help="show a saved design in Meshcat, served on 127.0.0.1",
        description="Serve the 3-D scene of a saved design on this machine only (127.0.0.1): the arm, each "
                    "spring as a helix coloured by its tension, animated through a sweep of each joint. "
                    "Prints the URL and serves until Ctrl-C.")
    view.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    view.add_argument("--port", type=_port, metavar="P", help="web port (default: the first free one from 7000)")
    view.add_argument("--open", action="store_true", help="also open the URL in the default web browser")
    view.add_argument("--frames", type=_positive_int, default=48, metavar="N",
                      help="animation frames per swept joint (default 48)")
    view.set_defaults(handler=_view)

    report = commands.add_parser(
        "report", parents=[common], help="write an HTML report of a saved design (tables, plots, 3-D scene)",
        description="Write FOLDER/report.html (design and metrics tables, plots), FOLDER/scene.html (the "
                    "self-contained Meshcat scene, opens without a server or network), FOLDER/torques.png/.svg "
                    "and FOLDER/histogram.png/.svg.")
    report.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    report.add_argument("--out", "-o", required=True, metavar="FOLDER", help="folder for the report (created)")
    report.add_argument("--workspace", "-w", metavar="WORKSPACE.yaml",
                        help="report on another workspace (as for 'evaluate')")
    report.add_argument("--no-scene", action="store_true", help="leave out scene.html")
    report.add_argument("--frames", type=_positive_int, default=48, metavar="N",
                        help="animation frames per swept joint in scene.html (default 48)")
    report.set_defaults(handler=_report)

    export = commands.add_parser(
        "export", parents=[common], help="write the balanced arm as a URDF with spring anchors and/or a MuJoCo model",
        description="Write the design's URDF with a massless link at every spring anchor and the spring "
                    "records (plus a .springs.json sidecar), and/or a MuJoCo model (MJCF) with a tendon per "
                    "spring. Springs whose real law MuJoCo's linear two-sided spring cannot express at some "
                    "workspace sample are listed as warnings; files are written atomically.")
    export.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    export.add_argument("--urdf", metavar="OUT.urdf", help="URDF to write (with OUT.springs.json next to it)")
    export.add_argument("--mjcf", metavar="OUT.xml", help="MuJoCo model to write")
    export.add_argument("--resolve-packages", action="store_true",
                        help="replace package:// mesh paths of the URDF by absolute paths")
    export.set_defaults(handler=_export)

    payload = commands.add_parser(
        "payload-range", parents=[common], help="anchor position against payload, and the largest payload, of a saved design",
        description="For a saved design with per-scenario variables (an adjustable anchor), keep the shared "
                    "variables and re-fit the per-scenario ones for each payload MASS at POINT of BODY; print the "
                    "table and the largest payload balanced to --max-residual. A design without per-scenario "
                    "variables prints its residual torque against the payload instead.")
    payload.add_argument("design", metavar="DESIGN.json", help="design file written by 'springbalance design'")
    payload.add_argument("--body", required=True, help="body (URDF link) that carries the payload")
    payload.add_argument("--point", type=float, nargs=3, default=(0.0, 0.0, 0.0), metavar=("X", "Y", "Z"),
                         help="payload position in the body frame [m] (default 0 0 0)")
    payload.add_argument("--masses", type=float, nargs="+", metavar="M", help="payloads of the table [kg]")
    payload.add_argument("--max-residual", type=float, metavar="R",
                         help="peak residual torque [N·m] up to which a payload counts as balanced "
                              "(default 1e-6 of the bare arm's peak gravity torque)")
    payload.add_argument("--plot", metavar="PATH", help="also save the plot as PATH.png and PATH.svg")
    payload.set_defaults(handler=_payload_range)

    robots = commands.add_parser(
        "robots", parents=[common], help="list the robots of example-robot-data",
        description="List the robot names accepted by 'mechanism: {robot: NAME}' in a config.")
    robots.add_argument("--paths", action="store_true", help="also print the URDF file of each robot")
    robots.set_defaults(handler=_robots)

    inspect = commands.add_parser(
        "inspect", parents=[common], help="list the bodies and joints of a robot or URDF (the names anchors and workspaces use)",
        description="Print the bodies (mass, centre of mass in the body frame, parent joint), the joints (type, "
                    "axis, limits, mimic coupling), the total mass and the ground bodies of an example-robot-data "
                    "robot or a URDF file: the names to write in a config's anchors and workspace.")
    inspect.add_argument("source", metavar="ROBOT_OR_URDF",
                         help="a URDF file (an existing file, or any path with a '/' or ending in .urdf or .xml) "
                              f"or an example-robot-data robot name (see '{PROG} robots')")
    inspect.add_argument("--json", action="store_true", help="print the description as JSON instead of tables")
    inspect.add_argument("--mimic", action="store_true",
                         help="couple mimic joints to their primary joints (as 'mechanism: {mimic: true}' in a config)")
    inspect.add_argument("--no-validate", action="store_true",
                         help="load a URDF whose masses, inertias or joint limits are physically impossible (as "
                              "'mechanism: {validate: false}' in a config); malformed numbers are still refused")
    inspect.set_defaults(handler=_inspect)

    explore = commands.add_parser(
        "explore", parents=[common], help="find where springs should go: solve every spring topology on Dask",
        description="Enumerate the spring topologies of a study config (a design config with an 'explore' "
                    "section instead of 'springs'), prune those that cannot balance exactly, solve the rest as "
                    "tasks on a Dask cluster (a local one with a worker process per core by default), and write "
                    "each result as it finishes into OUT/results/, then OUT/results.csv, OUT/report.html and "
                    "the best design per spring count (OUT/best_<k>_springs.json). Running it again resumes.")
    explore.add_argument("config", metavar="CONFIG", help="study config file (.yaml, .yml or .json)")
    explore.add_argument("--out", "-o", required=True, metavar="FOLDER", help="the study folder")
    explore.add_argument("--max-springs", type=int, metavar="N",
                         help="most springs per topology (overrides explore.max_springs; default 2)")
    explore.add_argument("--scheduler", metavar="ADDRESS",
                         help="run on an existing Dask cluster (e.g. tcp://host:8786) instead of a local one")
    explore.add_argument("--workers", type=_positive_int, metavar="W",
                         help="worker processes of the local cluster (default: one per core)")
    explore.add_argument("--timeout", type=float, default=10.0, metavar="SECONDS",
                         help="how long to wait for the scheduler given by --scheduler (default 10)")
    explore.add_argument("--sequential", action="store_true", help="solve the tasks one after another in this "
                                                                   "process (no Dask)")
    explore.add_argument("--force", action="store_true",
                         help="use a study folder that holds another study's results (they are discarded)")
    explore.add_argument("--quiet", "-q", action="store_true", help="no progress bar and no summary")
    explore.set_defaults(handler=_explore)

    schema = commands.add_parser(
        "schema", parents=[common], help="print the JSON Schema of config files",
        description="Print the JSON Schema (draft 2020-12) that config files follow, for editors (completion "
                    "and checking, e.g. with a '# yaml-language-server: $schema=PATH' first line) and other "
                    "validators; --out writes it to a file instead.")
    schema.add_argument("--out", "-o", metavar="PATH", help="write the schema to PATH (atomically) instead of stdout")
    schema.set_defaults(handler=_schema)
    return parser


# ---------------------------------------------------------------------- commands
def _explore(args) -> int:
    from springbalance.explore.study import load_study, make_client

    if args.max_springs is not None and args.max_springs < 1:
        raise InputError(f"--max-springs must be an integer ≥ 1, got {args.max_springs}")
    if args.sequential and (args.scheduler or args.workers):
        raise InputError("--sequential runs without Dask: it takes no --scheduler or --workers")
    study = load_study(args.config, max_springs=args.max_springs)
    # nothing left to solve (a finished study run again): no cluster to start
    client = None if args.sequential or not study.pending(args.out) else make_client(args.scheduler, args.workers,
                                                                                     args.timeout)
    try:
        result = study.run(args.out, client=client, force=args.force, progress=not args.quiet)
    finally:
        if client is not None:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None and args.scheduler is None:
                cluster.close()
    if not args.quiet:
        summary = study.summary()
        print(f"{len(study.candidates)} candidates, {summary['topologies']} topologies × {summary['grid_points']} "
              f"grid point(s); {summary['reachability']}: {len(summary['unreachable'])} proven unreachable, "
              f"{len(summary['degenerate'])} degenerate; {len(result.dominated)} dominated; solved "
              f"{len(result.solved)} now, {result.resumed} from an earlier run")
        for count, record in result.best().items():
            print(f"  best with {count} spring(s): {' + '.join(record['springs'])}  residual "
                  f"{record['relative_residual']:.3g} of the unbalanced peak{'  (exact)' if record['exact'] else ''}"
                  f"  -> {Path(args.out) / f'best_{count}_springs.json'}")
        print(f"report: {Path(args.out) / 'report.html'}")
    return 0


def _design(args) -> int:
    from springbalance.io.config import load_config
    from springbalance.pipeline import solve

    out = Path(args.out)
    _check_output(out)
    parts = None
    if args.stock is not None:  # a bad catalogue fails before the solve
        from springbalance.io.catalogue import read_catalogue

        parts = read_catalogue(args.stock)
    config = load_config(args.config)
    progress = False if args.quiet else None
    overrides = {"starts": args.starts, "seed": args.seed, "method": args.method, "workers": args.workers}
    try:
        result = solve(config, **overrides, progress=progress, stock=parts)
    except Interrupted as stop:
        return _interrupted(stop, out, args.partial)
    selection = result.stock
    _save_design(result, out, selection, args.stock)
    if not args.quiet:
        print(result.table())
        if selection is not None:
            print(f"\n{selection.summary()}")
        print(f"\ndesign saved to {out}")
    return 0


#: finished starts listed by name when a design is interrupted
MAX_STARTS_SHOWN = 8


def _interrupted(stop, out: Path, partial: bool) -> int:
    """Ctrl-C during ``design``: say which starts had finished; with ``--partial`` save the best so far."""
    from springbalance.results.result import DesignResult

    shown = [f"{record.index} ({record.objective:.4g}{'' if record.feasible else ', infeasible'})"
             for record in stop.starts[:MAX_STARTS_SHOWN]]
    more = len(stop.starts) - len(shown)
    finished = ", ".join(shown) + (f" and {more} more" if more > 0 else "")
    feasible = [record for record in stop.starts if record.feasible]
    if feasible:
        best = min(feasible, key=lambda record: record.objective)
        finished += f"; best objective {best.objective:.6g} (start {best.index})"
    if partial and stop.best_x is not None:
        result = DesignResult(stop.problem, stop.best_x, starts=stop.starts, method="interrupted", seed=None,
                              status=f"{stop} (the best design so far, saved with --partial)")
        _save_design(result, out)
        saved = f"; the best design so far is saved to {out}"
    elif partial:
        saved = "; no start had finished with a feasible design, so nothing is saved"
    else:
        saved = f"; nothing is saved ({out} is unchanged; --partial saves the best design so far)"
    print(f"{PROG}: {stop}{': starts ' + finished if finished else ''}{saved}", file=sys.stderr)
    return 130


def _save_design(result, out: Path, selection=None, catalogue: str | None = None) -> None:
    """Save ``result`` at ``out`` (atomically); a stock spring's ``part_number`` also goes into its
    ``design`` entry, and a stock selection into ``stock`` (catalogue, objective before/after, choices)."""
    from springbalance.files import write_json_atomic

    record = result.to_dict()
    for entry, spring in zip(record.get("design", []), result.problem.springs):
        if getattr(spring, "part_number", None) is not None:
            entry.setdefault("part_number", spring.part_number)
    if selection is not None:
        record["stock"] = {"catalogue": str(catalogue), **selection.to_dict()}
    write_json_atomic(out, record)


def _evaluate(args) -> int:
    from springbalance.io.config import load_workspace
    from springbalance.results.result import DesignResult

    result = DesignResult.load(args.design)
    if args.workspace is not None:
        workspace = load_workspace(args.workspace, result.problem.mechanism)
        result = DesignResult.load(args.design, mechanism=result.problem.mechanism, workspace=workspace)
    print(result.table())
    return 0


def _clearance(args) -> int:
    from springbalance.results.result import DesignResult

    result = DesignResult.load(args.design)
    report = result.clearance(radius=args.radius, samples=args.samples, margin=args.margin)
    print("\n".join(report.lines()))
    return 0


def _view(args) -> int:
    import time

    from springbalance.results.result import DesignResult
    from springbalance.viz.live import MeshcatServer
    from springbalance.viz.scene import DesignScene

    result = DesignResult.load(args.design)
    _check_scene_budget(result, args.frames)
    scene = DesignScene(result, frames_per_joint=args.frames)
    server = MeshcatServer(port=args.port)
    try:
        scene.draw(server.visualizer())
        print(f"{PROG}: the scene of {args.design} is at {server.web_url}")
        print(f"  {scene.color_scale.describe()}")
        if scene.skipped:
            print(f"  not drawn (they act in a joint): {', '.join(scene.skipped)}")
        print("  press Ctrl-C to stop", flush=True)
        if args.open:
            import webbrowser

            webbrowser.open(server.web_url, new=2)
        while server.running:
            time.sleep(0.25)
        raise SpringBalanceError("the meshcat server stopped unexpectedly")
    except KeyboardInterrupt:
        print(f"{PROG}: stopped", flush=True)
        return 0
    finally:
        server.stop()


def _report(args) -> int:
    from springbalance.results.result import DesignResult

    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {str(out)!r} is a file; give a folder")
    result = DesignResult.load(args.design)
    if args.workspace is not None:
        from springbalance.io.config import load_workspace

        workspace = load_workspace(args.workspace, result.problem.mechanism)
        result = DesignResult.load(args.design, mechanism=result.problem.mechanism, workspace=workspace)
    if not args.no_scene:
        _check_scene_budget(result, args.frames)
    path = result.report(out, scene=not args.no_scene, frames_per_joint=args.frames)
    files = ["report.html"] + ([] if args.no_scene else ["scene.html"]) + [
        "torques.png", "torques.svg", "histogram.png", "histogram.svg"]
    print(f"report written to {path}")
    print(f"  files in {out}: {', '.join(files)}")
    return 0


def _export(args) -> int:
    from springbalance.export.common import law_warnings
    from springbalance.export.mjcf import mjcf_string
    from springbalance.export.urdf import sidecar_path, urdf_strings
    from springbalance.files import write_text_atomic
    from springbalance.results.result import DesignResult

    if args.urdf is None and args.mjcf is None:
        raise InputError("export: give --urdf OUT.urdf and/or --mjcf OUT.xml")
    for option, value, example in (("--urdf", args.urdf, "balanced.urdf"), ("--mjcf", args.mjcf, "balanced.xml")):
        if value is not None:
            _check_output(Path(value), option, example)
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


def _payload_range(args) -> int:
    import numpy as np

    from springbalance.results.payload import payload_range, residual_vs_payload
    from springbalance.results.result import DesignResult

    result = DesignResult.load(args.design)
    if args.body not in result.problem.mechanism.body_names:
        raise InputError(f"--body: unknown body {args.body!r}; bodies: {', '.join(result.problem.mechanism.body_names)}")
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


def _robots(args) -> int:
    from springbalance.model.robots import available_robots

    robots = available_robots()
    width = max((len(name) for name in robots), default=0)
    for name, path in robots.items():
        print(f"{name:<{width}s}  {path}" if args.paths else name)
    return 0


def _inspect(args) -> int:
    import json

    summary = _load_mechanism(args.source, mimic=args.mimic, validate=not args.no_validate).summary()
    print(json.dumps(summary, indent=2) if args.json else _summary_text(summary))
    return 0


def _load_mechanism(argument: str, mimic: bool = False, validate: bool = True):
    """The URDF file ``argument`` if it is a file or looks like a path, else the robot of that name."""
    from springbalance.model.mechanism import Mechanism

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


def _summary_text(summary: dict) -> str:
    """The text tables of ``springbalance inspect`` for a :meth:`Mechanism.summary` dict."""
    import math

    source = summary["source"]
    where = {"robot": f"example-robot-data robot {source.get('robot')!r}, {source.get('path')}",
             "urdf": f"URDF {source.get('path')}"}.get(source.get("kind"), source.get("kind"))
    if source.get("mimic"):
        where += ", mimic joints coupled"
    dof_names = [joint["name"] for joint in summary["joints"] if joint["dof"]]
    lines = [
        f"{summary['name']} ({where})",
        f"  {summary['dofs']} degree{'' if summary['dofs'] == 1 else 's'} of freedom: {', '.join(dof_names) or '—'}",
        f"  total mass {_g(summary['total_mass'])} kg, of which {_g(summary['moving_mass'])} kg moves",
        f"  gravity ({', '.join(_g(value) for value in summary['gravity'])}) m/s²",
        f"  ground (cannot move): {', '.join(summary['ground'])}",
        "",
        "bodies (centre of mass in the body frame)",
    ]
    rows = [[body["name"], _g(body["mass"]), "(" + ", ".join(_g(value) for value in body["com"]) + ")",
             body["parent_joint"] or "—", "ground" if body["ground"] else body["moved_by"]]
            for body in summary["bodies"]]
    lines += _table(["body", "mass [kg]", "centre of mass [m]", "parent joint", "moved by"], rows, right=(1,))
    lines += ["", "joints (axis in the joint frame)"]
    rows = []
    for joint in summary["joints"]:
        axis = "—" if joint["axis"] is None else "(" + ", ".join(_g(value) for value in joint["axis"]) + ")"
        if joint["mimic"] is not None:
            mimic = joint["mimic"]
            limits = f"mimic: {_g(mimic['multiplier'])} × {mimic['joint']} + {_g(mimic['offset'])}"
        elif joint["lower"] is None:
            limits = "—"
        else:
            limits = f"{_g(joint['lower'], 5)} … {_g(joint['upper'], 5)} {joint['unit']}"
            if joint["unit"] == "rad":
                lower, upper = (round(math.degrees(joint[end]), 1) for end in ("lower", "upper"))
                limits += f" ({_g(lower)}° … {_g(upper)}°)"
            if joint["type"] == "continuous":
                limits += ", no stops"
        rows.append([joint["name"], joint["type"], f"{joint['parent']} → {joint['child']}", axis, limits])
    lines += _table(["joint", "type", "parent → child", "axis", "limits"], rows)
    return "\n".join(lines)


def _table(header: list[str], rows: list[list[str]], right: tuple[int, ...] = ()) -> list[str]:
    """Lines of a table indented by two spaces, columns padded to their widest cell."""
    widths = [max(len(str(row[column])) for row in [header, *rows]) for column in range(len(header))]
    lines = []
    for row in [header, *rows]:
        cells = [f"{str(cell):>{width}s}" if column in right else f"{str(cell):<{width}s}"
                 for column, (cell, width) in enumerate(zip(row, widths))]
        lines.append(("  " + "  ".join(cells)).rstrip())
    return lines


def _g(value: float, digits: int = 6) -> str:
    """``value`` with ``digits`` significant digits, without a negative zero."""
    return f"{value + 0.0:.{digits}g}"


def _schema(args) -> int:
    from springbalance.files import write_text_atomic
    from springbalance.io.schema import schema_text

    text = schema_text()
    if args.out is None:
        sys.stdout.write(text)
        return 0
    _check_output(Path(args.out), example="config.schema.json")
    write_text_atomic(args.out, text)
    print(f"schema written to {args.out}")
    return 0


# ---------------------------------------------------------------------- helpers
def _check_scene_budget(result, frames_per_joint: int) -> None:
    """Refuse (--frames too large) a scene whose estimated memory is above the limit, before drawing it."""
    from springbalance.model import budget
    from springbalance.model.sweeps import moving_joints

    frames = frames_per_joint * max(len(moving_joints(result)), 1) + 1
    objects = len(result.problem.mechanism.body_names) + len(result.problem.springs)
    budget.require(budget.scene_bytes(frames, objects),
                   f"a scene of {frames} frames (--frames {frames_per_joint} per moving joint) and {objects} objects")


def _check_output(out: Path, option: str = "--out", example: str = "design.json") -> None:
    """Fail before solving (or exporting) when the file could not be saved at ``out``."""
    if out.is_dir():
        raise InputError(f"{option} {str(out)!r} is a directory; give a file name such as {example}")
    folder = out.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise InputError(f"{option} {str(out)!r}: {str(folder)!r} is not a directory")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{option} {str(out)!r}: folder {str(folder)!r} is not writable")


def _print_error(error) -> None:
    message = " ".join(str(error).split()) or type(error).__name__
    print(f"{PROG}: error: {message}", file=sys.stderr)


def _positive_int(text: str) -> int:
    value = _nonnegative_int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be ≥ 1, got {text!r}")
    return value


def _port(text: str) -> int:
    value = _nonnegative_int(text)
    if not 1 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"a port is 1 … 65535, got {text!r}")
    return value


def _nonnegative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be ≥ 0, got {text!r}")
    return value


if __name__ == "__main__":  # pragma: no cover
    run()
