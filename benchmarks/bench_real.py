"""Real designs on real arms: each case at its default settings, against a 4× search and over 5 seeds, checked densely.

The cases are config files (benchmarks/real/*.yaml, and the shipped examples/ur5.yaml and examples/panda.yaml),
solved as a user solves them (``sb.solve(config)``: the config's ``solve`` section, nothing else):

  ur5-ideal          UR5, 4 ideal extension springs on the shoulder, upper arm and forearm, ±0.3 m boxes
  ur5-ground         UR5, the same 4 ideal springs, two of them from the ground (bench_ur5.py's topology)
  ur5-coils          UR5, the 4 springs of ur5-ideal as helical coils of at most 40 mm outer diameter
  ur5-coils-clear    ur5-coils kept 5 mm clear of the arm's collision meshes (+ its ideal twin, part d)
  ur5-mounted-clear  UR5, 3 ideal springs whose anchors sit on the links' surfaces (``on: collision``), clear
  ur5-mounted-coils-clear  ur5-mounted-clear as coils of at most 40 mm: what an engineer builds
  panda-ideal        Panda, 4 ideal springs on links 1–4 (upper-arm roll held, fingers held; the spring that
                     spans the roll in the arm's plane)
  panda-coils-clear  Panda, the same 4 springs as coils of at most 40 mm, kept 5 mm clear (the one across the roll
                     free beside the plane: in it, no coil passes the upper arm)
  example-ur5        examples/ur5.yaml (the shipped example, sized to run in about a minute)
  example-panda      examples/panda.yaml (shipped: two shoulder coils beside the arm, one elbow coil in its plane)

Per case, in the same run:

  (a) default:   the config as it is;
  (b) search:    4× ``solve.starts`` and 4× ``clearance.starts`` (the fitted starts), same seed;
  (c) seeds:     the default with ``solve.seed`` 0..S-1 (S = --seeds, 5; the default's own seed is reused).

and, per joint with a weight > 0 that gravity loads, the RMS cut (%) of each run: 100·(1 − RMS(τ)/RMS(g))
over the design's samples. "best" is the design of lowest objective among the runs (the runs whose clearance
fit converged, when the case has a clearance); the gap is cut(best) − cut(default) per joint (goal ≤ 1
point), the spread is max − min of the cut over the seeds (goal ≤ 1 point); the design `--seeds` over those seeds
would keep (the first that passes every check, by objective) is printed with their time in all. (d) For a case with an ideal
twin (ur5-coils-clear), the same problem with ideal springs (k in [0, 5000] N/m, l0 in [0.05, 1] m) and no
clearance is solved at its default too: the loss per joint, cut(ideal) − cut(coils+clearance) (goal ≤ 2
points), and the time ratio (goal ≤ 10×). So is its floor: the coils without clearance, searched with 4× the
starts; every design with clearance is one without it, so where the ideal → coils loss of that search is
above 2 points, the goal is beyond what any design found here reaches (the coils' rules alone cost it).

Every default and search design is verified independently of the solve:

  - dense residual: the design evaluated (not re-solved) on --dense Sobol poses (16,384; seed 7, a
    different sequence from the design's) over the config's ranges: the RMS cut there per joint and the
    largest violation of the design's rows (coil rules, keep_tension) at those unseen poses, and of its rules
    (a row plus the reserve the optimisation keeps: the rule itself, as the verification judges it);
  - clearance: ``result.clearance(samples=10 × clearance.check_samples)`` (coal against the URDF's own
    meshes, not their hulls): the smallest distance of each spring and its closest link; a case with a
    clearance passes when no spring comes below the margin (cases without one are reported, not judged).

Times are wall times of building the problem and solving it (``config_from_dict`` + ``sb.solve``), with the
default workers (both cores). Each case runs alone with --cases; --parts picks a subset of a, b, c, d (the
dense checks go with a and b).

Run: .venv/bin/python benchmarks/bench_real.py [--cases ur5-ideal,panda-ideal] [--parts abcd] [--seeds 5]
     [--samples N] [--dense 16384] [--quick] [--json OUT]
(make bench-real; the whole suite takes hours on 2 cores: a UR5 coil+clearance solve at 1,024 samples
takes about 10 minutes, and (b) and (c) repeat it; --quick is a smoke run of minutes)
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import springbalance as sb
from springbalance.io.config import config_from_dict, read_config_file, workspace_from_dict
from springbalance.results.seed_search import SeedRun, best_run

ROOT = Path(__file__).resolve().parent.parent
REAL = ROOT / "benchmarks" / "real"

GAP_GOAL = 1.0  # [percentage points] default → best found
SPREAD_GOAL = 1.0  # [percentage points] over the seeds
LOSS_GOAL = 2.0  # [percentage points] ideal unconstrained → coils + clearance
RATIO_GOAL = 10.0  # time of coils + clearance / time of the ideal twin


@dataclass(frozen=True)
class Case:
    name: str
    path: Path
    twin: bool = False  # (d): also solve the ideal, unconstrained twin


CASES = [
    Case("ur5-ideal", REAL / "ur5_ideal.yaml"),
    Case("ur5-ground", REAL / "ur5_ground.yaml"),
    Case("ur5-coils", REAL / "ur5_coils.yaml"),
    Case("ur5-coils-clear", REAL / "ur5_coils_clear.yaml", twin=True),
    Case("ur5-mounted-clear", REAL / "ur5_mounted_clear.yaml"),
    Case("ur5-mounted-coils-clear", REAL / "ur5_mounted_coils_clear.yaml"),
    Case("panda-ideal", REAL / "panda_ideal.yaml"),
    Case("panda-coils-clear", REAL / "panda_coils_clear.yaml"),
    Case("example-ur5", ROOT / "examples" / "ur5.yaml"),
    Case("example-panda", ROOT / "examples" / "panda.yaml"),
]
BY_NAME = {case.name: case for case in CASES}

#: the ideal twin's spring parameters (bench_clearance.py's)
IDEAL = {"ideal": True, "stiffness": {"lower": 0, "upper": 5000}, "free_length": {"lower": 0.05, "upper": 1.0}}
COIL_KEYS = ("max_outer_diameter", "material", "ends", "wire_diameter", "coil_diameter", "active_coils")


def arguments() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default=",".join(BY_NAME), help="comma-separated case names (default: all)")
    parser.add_argument("--parts", default="abcd", help="subset of abcd (default: all)")
    parser.add_argument("--seeds", type=int, default=5, help="seeds of (c): 0..N-1")
    parser.add_argument("--samples", type=int, help="workspace samples of every case (default: the config's)")
    parser.add_argument("--dense", type=int, default=16384, help="Sobol poses of the dense residual check")
    parser.add_argument("--quick", action="store_true", help="smoke run: 64 samples, 2 starts, 64 check poses, 2 seeds")
    parser.add_argument("--json", metavar="OUT", help="save every figure as JSON")
    args = parser.parse_args()
    unknown = [name for name in args.cases.split(",") if name not in BY_NAME]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)}; known: {', '.join(BY_NAME)}")
    if not set(args.parts) <= set("abcd"):
        parser.error(f"--parts {args.parts!r}: letters of abcd only")
    if args.quick:
        args.samples = args.samples or 64
        args.seeds = min(args.seeds, 2)
        args.dense = min(args.dense, 2048)
    return args


# ---------------------------------------------------------------------- configs
def case_record(case: Case, args: argparse.Namespace) -> dict[str, Any]:
    """The case's config mapping, with --samples and --quick applied."""
    record = read_config_file(case.path)
    if args.samples:
        record["workspace"]["n"] = args.samples
    if args.quick:
        record.setdefault("solve", {})["starts"] = 2  # the first start alone is the boxes' middle
        if "clearance" in record:
            record["clearance"]["check_samples"] = 64
    return record


def search_record(record: dict[str, Any]) -> dict[str, Any]:
    """(b): 4× the starts of the multi-start and 4× the fitted starts of the clearance loop."""
    wider = copy.deepcopy(record)
    solve = wider.setdefault("solve", {})
    solve["starts"] = 4 * solve.get("starts", 8)
    if "clearance" in wider:
        wider["clearance"]["starts"] = 4 * wider["clearance"].get("starts", 1)
    return wider


def ideal_twin(record: dict[str, Any]) -> dict[str, Any]:
    """(d): the same problem with ideal extension springs and no clearance."""
    twin = coils_only(record)
    for spring in twin["springs"]:
        for key in COIL_KEYS:
            spring.pop(key, None)
        spring.update(copy.deepcopy(IDEAL))
    return twin


def coils_only(record: dict[str, Any]) -> dict[str, Any]:
    """(d): the case without its clearance, and so without mounting on surfaces (an anchor mounted on a
    surface is held there by the clearance loop only): its anchors free in their boxes."""
    alone = copy.deepcopy(record)
    alone.pop("clearance", None)
    for spring in alone["springs"]:
        for end in ("a", "b"):
            if spring[end].get("on") == "collision":
                spring[end].pop("on")
                spring[end].pop("offset", None)
    return alone


# ---------------------------------------------------------------------- runs
def solve(record: dict[str, Any], case: Case, label: str, seed: int | None = None) -> dict[str, Any]:
    """Build and solve the config ``record``; the design, its time and its figures (``error`` when the
    solve fails: no feasible start, a crash; the suite goes on)."""
    clock = time.perf_counter()
    try:
        config = config_from_dict(copy.deepcopy(record), base_dir=case.path.parent, label=f"{case.name} ({label})")
        result = sb.solve(config, seed=seed, progress=False)
    except Exception as error:  # a benchmark reports a failed solve and goes on
        message = " ".join(f"{type(error).__name__}: {error}".split())[:300]
        return {"label": label, "seconds": time.perf_counter() - clock, "error": message, "result": None}
    seconds = time.perf_counter() - clock
    metrics = result.metrics()
    fit = result.fit
    return {
        "label": label,
        "seconds": seconds,
        "objective": float(metrics["objectives"][metrics["optimised"]]["after"]),
        "cuts": cuts(result, metrics),
        "fit": None if fit is None else {"rounds": fit.rounds, "converged": fit.converged, "seconds": fit.seconds},
        "status": result.status,
        # what would make the CLI exit 3 (not converged, not verified, overlapping, a joint made worse, ...)
        "failures": sorted({flag.kind for flag in result.failures()}),
        "result": result,
    }


def cuts(result: sb.DesignResult, metrics: dict[str, Any] | None = None) -> dict[str, float]:
    """RMS cut [%] of every joint with a weight > 0 that gravity loads (a finite reduction)."""
    weights = result.problem.weights_by_name()
    metrics = metrics or result.metrics()
    return {
        row["joint"]: float(row["rms_reduction_percent"])
        for row in metrics["joints"]
        if weights.get(row["joint"], 1.0) > 0 and math.isfinite(row["rms_reduction_percent"])
    }


def feasible(run: dict[str, Any]) -> bool:
    """A design that counts as found: no clearance, or a clearance fit that converged."""
    return run["fit"] is None or bool(run["fit"]["converged"])


def solved(runs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The runs that gave a design."""
    return [run for run in runs if "error" not in run]


def rule_violation(result: Any, evaluated: Any) -> float:
    """The largest violation of a rule at the poses of ``evaluated`` [the row's unit]: a per-sample row plus the
    reserve the optimisation keeps (as the verification judges it, docs/model.md §12), leaving out a coil's
    fatigue bounds (auxiliary: the verification judges the damage rows at the force range met instead)."""
    rows = evaluated.evaluation.constraint_rows
    worst = [
        -(float(rows[:, block.offset].min()) + block.reserve)
        for block in evaluated.problem.model.constraint_blocks
        if block.per_sample and block.name not in ("fatigue_floor", "fatigue_ceiling") and rows.size
    ]
    return max([0.0, *worst])


def dense_check(run: dict[str, Any], record: dict[str, Any], case: Case, args: argparse.Namespace) -> dict[str, Any]:
    """The design on --dense unseen Sobol poses and its clearance at 10× the fitting check's poses."""
    result = run["result"]
    mechanism = result.problem.mechanism
    dense = copy.deepcopy(record["workspace"])
    dense.update(kind="sobol", n=args.dense, seed=7)
    workspace = workspace_from_dict(mechanism, dense, case.path.parent, f"{case.name}: dense workspace")
    clock = time.perf_counter()
    evaluated = result.on_workspace(workspace)
    check: dict[str, Any] = {
        "dense_poses": workspace.size,
        "dense_cuts": cuts(evaluated),
        "dense_max_violation": float(evaluated.evaluation.max_violation),
        "dense_rule_violation": rule_violation(result, evaluated),
    }
    clearance = record.get("clearance")
    margin = float(clearance.get("margin", 0.005)) if clearance else 0.005
    poses = 10 * int(clearance.get("check_samples", 1024) if clearance else 512)
    report = result.clearance(samples=poses, margin=margin)
    check.update(
        clearance_poses=report.poses,
        margin=margin,
        judged=clearance is not None,
        clear=report.clear,
        springs={row.spring: {"distance": row.distance, "link": row.link} for row in report.rows},
        seconds=time.perf_counter() - clock,
    )
    return check


# ---------------------------------------------------------------------- printing
def joint_label(name: str) -> str:
    return name.removesuffix("_joint")


def print_runs(runs: list[dict[str, Any]], joints: list[str]) -> None:
    head = f"  {'run':<18}{'time [s]':>10}{'objective':>12}" + "".join(f"{joint_label(j):>16}" for j in joints)
    print(head + "   fit")
    for run in runs:
        if "error" in run:
            print(f"  {run['label']:<18}{run['seconds']:>10.1f}   FAILED: {run['error']}")
            continue
        fit = run["fit"]
        fitted = "" if fit is None else f"   {fit['rounds']} round(s){'' if fit['converged'] else ', NOT converged'}"
        cells = "".join(f"{run['cuts'].get(j, float('nan')):>16.2f}" for j in joints)
        fails = f"   FAILS: {', '.join(run['failures'])}" if run.get("failures") else ""
        print(f"  {run['label']:<18}{run['seconds']:>10.1f}{run['objective']:>12.5g}{cells}{fitted}{fails}")


def print_check(label: str, check: dict[str, Any], design_cuts: dict[str, float]) -> None:
    moved = ", ".join(
        f"{joint_label(j)} {cut:.2f} % ({cut - design_cuts[j]:+.2f})"
        for j, cut in check["dense_cuts"].items()
        if j in design_cuts
    )
    print(
        f"  dense check of {label}: {check['dense_poses']} unseen poses: {moved}; "
        f"largest row violation {check['dense_max_violation']:.3g} (of a rule, its reserve added back: "
        f"{check['dense_rule_violation']:.3g})"
    )
    springs = ", ".join(
        f"{name} {row['distance'] * 1e3:.1f} mm ({row['link']})" for name, row in check["springs"].items()
    )
    verdict = (
        ("PASS (clear)" if check["clear"] else f"MISS (a spring below {check['margin'] * 1e3:g} mm)")
        if check["judged"]
        else "(no clearance asked: not judged)"
    )
    print(f"  clearance of {label} at {check['clearance_poses']} poses: {springs} → {verdict}")


def verdict(value: float, goal: float) -> str:
    return "PASS" if value <= goal else "MISS"


# ---------------------------------------------------------------------- one case
def run_case(case: Case, args: argparse.Namespace) -> dict[str, Any]:
    record = case_record(case, args)
    print(f"\n== {case.name}: {case.path.relative_to(ROOT)}, {record['workspace'].get('n', 1024)} samples")
    out: dict[str, Any] = {"case": case.name, "config": str(case.path.relative_to(ROOT))}
    default_seed = int(record.get("solve", {}).get("seed", 0))
    runs: list[dict[str, Any]] = []
    if "a" in args.parts:
        runs.append(solve(record, case, "default (a)"))
        runs[-1]["seed"] = default_seed
    if "b" in args.parts:
        runs.append(solve(search_record(record), case, "4x search (b)"))
    if "c" in args.parts:
        for seed in range(args.seeds):
            if seed == default_seed and "a" in args.parts:
                continue
            runs.append(solve(record, case, f"seed {seed} (c)", seed=seed))
            runs[-1]["seed"] = seed
    out["runs"] = [{key: value for key, value in run.items() if key != "result"} for run in runs]
    designs = solved(runs)
    if not designs:
        print_runs(runs, [])
        return out
    # a joint no spring crosses keeps its whole load in every run (a wrist): listed, not judged
    unreached = [j for j in designs[0]["cuts"] if all(abs(run["cuts"][j]) < 1e-6 for run in designs)]
    joints = [j for j in designs[0]["cuts"] if j not in unreached]
    print_runs(runs, joints)
    if unreached:
        print(f"  no spring acts on {', '.join(unreached)} (0 % cut in every run): not judged")
    out["unreached"] = unreached
    out.update(goals(runs, joints))
    for run in designs:
        if run["label"].startswith(("default", "4x")):
            check = dense_check(run, record, case, args)
            print_check(run["label"], check, {j: run["cuts"][j] for j in joints})
            out.setdefault("checks", {})[run["label"]] = check
    if "d" in args.parts and case.twin and "error" not in runs[0] and runs[0]["label"].startswith("default"):
        out["twin"] = twin_part(record, case, runs[0], joints)
    return out


def goals(runs: list[dict[str, Any]], joints: list[str]) -> dict[str, Any]:
    """Gap of the default to the best found, spread over the seeds: printed with PASS/MISS, returned.

    A failed run counts as a MISS of the goal it belongs to (the default, or a seed)."""
    out: dict[str, Any] = {}
    default = next((run for run in runs if run["label"].startswith("default")), None)
    designs = solved(runs)
    pool = [run for run in designs if feasible(run)] or designs
    best = min(pool, key=lambda run: run["objective"]) if pool else None
    if default is not None and len(runs) > 1:
        if best is None:
            print("  gap default → best: every run failed → MISS")
            out["gap"] = {"best": None, "points": None, "pass": False}
        elif "error" in default:
            print("  gap default → best: the default failed → MISS")
            out["gap"] = {"best": best["label"], "points": None, "pass": False}
        else:
            gap = {j: best["cuts"][j] - default["cuts"][j] for j in joints}
            worst = max(gap.values(), default=0.0)
            cells = ", ".join(f"{joint_label(j)} {value:+.2f}" for j, value in gap.items())
            note = "" if any(feasible(run) for run in designs) else " (no fit converged: best of all)"
            print(f"  gap default → best ({best['label']}{note}) [points]: {cells} → {verdict(worst, GAP_GOAL)}")
            out["gap"] = {"best": best["label"], "points": gap, "pass": worst <= GAP_GOAL}
    seeded = [run for run in runs if "seed" in run]
    if len(seeded) > 1:
        good = solved(seeded)
        spread = {j: max(r["cuts"][j] for r in good) - min(r["cuts"][j] for r in good) for j in joints} if good else {}
        worst = max(spread.values(), default=0.0)
        failed = len(seeded) - len(good)
        cells = ", ".join(f"{joint_label(j)} {value:.2f}" for j, value in spread.items())
        times = [run["seconds"] for run in seeded]
        print(
            f"  spread over {len(seeded)} seeds [points]: {cells}{f', {failed} FAILED' if failed else ''} → "
            f"{verdict(worst, SPREAD_GOAL) if not failed else 'MISS'}; "
            f"time {min(times):.1f}–{max(times):.1f} s (mean {sum(times) / len(times):.1f})"
        )
        out["spread"] = {
            "seeds": len(seeded),
            "failed": failed,
            "points": spread,
            "pass": worst <= SPREAD_GOAL and not failed,
        }
        out["seeds"] = seeds_kept(seeded, joints)
    return out


def seeds_kept(seeded: list[dict[str, Any]], joints: list[str]) -> dict[str, Any] | None:
    """What ``--seeds`` over the seeds run here would keep (the library's rule, :func:`best_run`), printed and
    returned: its seed, objective, cuts and outcome, and the seeds' time in all (None when no seed gave a design)."""
    kept = best_run([SeedRun(r["seed"], r.get("objective"), tuple(r.get("failures", ()))) for r in seeded])
    if kept is None:
        return None
    run = next(r for r in seeded if r["seed"] == kept.seed)
    seconds = sum(r["seconds"] for r in seeded)
    cells = " / ".join(f"{run['cuts'][j]:.2f}" for j in joints)
    outcome = "passes" if kept.ok else ", ".join(kept.failures)
    seeds = ",".join(str(r["seed"]) for r in seeded)
    print(f"  --seeds {seeds} keeps seed {kept.seed}: {run['objective']:.5g}, {cells} %, {outcome} ({seconds:.1f} s)")
    return {"seed": kept.seed, "objective": run["objective"], "cuts": run["cuts"], "ok": kept.ok, "seconds": seconds}


def twin_part(record: dict[str, Any], case: Case, default: dict[str, Any], joints: list[str]) -> dict[str, Any]:
    """(d): the ideal unconstrained twin at its default; loss per joint and time ratio; and the coils' floor:
    the same coils without clearance, searched with 4× the starts (every design of the case with clearance
    is a design without it, so a loss that the coils alone cannot avoid is a floor of the goal)."""
    twin = solve(ideal_twin(record), case, "ideal twin (d)")
    floor = solve(search_record(coils_only(record)), case, "coils alone 4x (d)")
    print_runs([twin, floor], joints)
    if "error" in twin:
        return {"run": {key: value for key, value in twin.items() if key != "result"}}
    loss = {j: twin["cuts"][j] - default["cuts"][j] for j in joints}
    floors = {j: twin["cuts"][j] - floor["cuts"][j] for j in joints} if "error" not in floor else {}
    ratio = default["seconds"] / twin["seconds"]
    cells = ", ".join(f"{joint_label(j)} {value:+.2f}" for j, value in loss.items())
    print(f"  loss ideal → {case.name} [points]: {cells} → {verdict(max(loss.values()), LOSS_GOAL)}")
    if floors:
        above = [joint_label(j) for j, value in floors.items() if value > LOSS_GOAL]
        cells = ", ".join(f"{joint_label(j)} {value:+.2f}" for j, value in floors.items())
        print(
            f"  floor: loss ideal → coils without clearance (4x search) [points]: {cells}"
            + (f" → above the goal on {', '.join(above)}: the coils' rules alone cost more" if above else "")
        )
        cells = ", ".join(f"{joint_label(j)} {floor['cuts'][j] - default['cuts'][j]:+.2f}" for j in joints)
        print(f"  cost of the clearance: coils without it (4x) → {case.name} [points]: {cells}")
    print(
        f"  time ratio {case.name} / ideal twin: {default['seconds']:.1f} s / {twin['seconds']:.1f} s = "
        f"×{ratio:.1f} → {verdict(ratio, RATIO_GOAL)}"
    )
    return {
        "run": {key: value for key, value in twin.items() if key != "result"},
        "floor_run": {key: value for key, value in floor.items() if key != "result"},
        "loss_points": loss,
        "floor_points": floors,
        "loss_pass": max(loss.values()) <= LOSS_GOAL,
        # every joint that misses the goal also misses it with the coils alone: the goal is beyond the floor
        "loss_floor": bool(floors) and all(floors[j] > LOSS_GOAL for j in joints if loss[j] > LOSS_GOAL),
        "time_ratio": ratio,
        "ratio_pass": ratio <= RATIO_GOAL,
    }


# ---------------------------------------------------------------------- summary
def outcome(run: dict[str, Any] | None) -> str:
    """The default run's outcome: ``ok`` (the CLI exits 0), ``fails`` (a design the CLI refuses, exit 3:
    not converged, not verified, overlapping, a joint made worse), ``error`` (no design: no feasible start, a
    crash), ``-`` (not run)."""
    if run is None:
        return "-"
    if "error" in run:
        return "error"
    return "fails" if run.get("failures") else "ok"


def summary(cases: list[dict[str, Any]]) -> None:
    print(
        "\nSummary (PASS/MISS per goal; - where the part was not run; FLOOR: the loss misses, and so do the coils alone;"
        "\n outcome of the default: ok, fails (the CLI would refuse the design, exit 3) or error (no design))"
    )
    print(
        f"  {'case':<24}{'default [s]':>12}{'outcome':>8}{'gap ≤ 1':>10}{'spread ≤ 1':>12}{'clear':>8}"
        f"{'loss ≤ 2':>10}{'time ≤ 10×':>12}"
    )

    def mark(flag: bool | None) -> str:
        return "-" if flag is None else ("PASS" if flag else "MISS")

    for case in cases:
        default = next((run for run in case.get("runs", []) if run["label"].startswith("default")), None)
        check = case.get("checks", {}).get("default (a)")
        clear = check["clear"] if check and check["judged"] else None
        twin = case.get("twin", {})
        print(
            f"  {case['case']:<24}{default['seconds'] if default else float('nan'):>12.1f}"
            f"{outcome(default):>8}"
            f"{mark(case.get('gap', {}).get('pass')):>10}{mark(case.get('spread', {}).get('pass')):>12}"
            f"{mark(clear):>8}{'FLOOR' if twin.get('loss_floor') else mark(twin.get('loss_pass')):>10}"
            f"{mark(twin.get('ratio_pass')):>12}"
        )


def main() -> None:
    args = arguments()
    print(
        f"bench_real: parts {args.parts}, {args.seeds} seeds, dense check {args.dense} poses"
        f"{', QUICK (smoke run: the figures mean nothing)' if args.quick else ''}"
    )
    clock = time.perf_counter()
    cases = []
    for name in args.cases.split(","):
        cases.append(run_case(BY_NAME[name], args))
        if args.json:  # after every case: a run of hours keeps what it measured
            Path(args.json).write_text(json.dumps({"args": vars(args), "cases": cases}, indent=1, default=str))
    summary(cases)
    print(f"\ntotal {time.perf_counter() - clock:.0f} s")
    if args.json:
        print(f"saved {args.json}")


if __name__ == "__main__":
    main()
