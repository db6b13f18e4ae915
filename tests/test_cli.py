"""The ``springbalance`` command line: design/evaluate round trip, exit codes, one-line errors."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from config_helpers import SHOULDER_SPRING, edited_record
from springbalance.cli import build_parser, main
from springbalance.results.result import FORMAT

ROOT = Path(__file__).resolve().parents[1]
URDF = ROOT / "urdf" / "two_link_planar.urdf"

# One spring from just above the shoulder to link1; the elbow is held straight, so the
# shoulder carries a single-link load that one extension spring balances well.
BASE = {
    "mechanism": {"urdf": str(URDF)},
    "workspace": {
        "kind": "sobol",
        "n": 64,
        "seed": 0,
        "degrees": True,
        "ranges": {"shoulder": [-90, 90], "elbow": [0, 0]},
    },
    "springs": [SHOULDER_SPRING],
    "objective": "rms",
    "weights": {"elbow": 0.0},
    "solve": {"starts": 2, "seed": 0},
}


def write_config(tmp_path: Path, record=None, name: str = "config.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(BASE if record is None else record, sort_keys=False))
    return path


def edited(**changes) -> dict:
    """A deep copy of BASE with ``section__key=value`` changes."""
    return edited_record(BASE, **changes)


def run_error(capsys, argv, code=2) -> str:
    """Run ``main(argv)``, expect exit ``code`` and one error line on stderr; return that line."""
    assert main(argv) == code
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("springbalance: error: ")
    assert "Traceback" not in captured.err
    assert captured.out == ""
    return lines[0]


# ---------------------------------------------------------------------- round trip
def test_design_then_evaluate_round_trip(tmp_path, capsys):
    config = write_config(tmp_path)
    out = tmp_path / "results" / "design.json"
    assert main(["design", str(config), "--out", str(out), "--starts", "2", "--seed", "1"]) == 0
    printed = capsys.readouterr().out
    assert "Actuator torque (gravity only vs with springs)" in printed
    assert f"design saved to {out}" in printed

    record = json.loads(out.read_text())
    assert record["format"] == FORMAT
    assert record["solver"]["seed"] == 1 and len(record["solver"]["starts"]) == 2
    shoulder = record["metrics"]["joints"][0]
    assert shoulder["joint"] == "shoulder"
    assert shoulder["rms_reduction_percent"] > 80  # one spring nearly balances a single link

    assert main(["evaluate", str(out)]) == 0
    evaluated = capsys.readouterr().out
    # Same design, same workspace: the shoulder row of the report is identical.
    shoulder_row = next(line for line in printed.splitlines() if line.strip().startswith("shoulder ["))
    assert shoulder_row in evaluated.splitlines()
    assert "64 samples" in evaluated

    workspace = tmp_path / "workspace.yaml"
    workspace.write_text(yaml.safe_dump({"workspace": {"kind": "grid", "n": {"shoulder": 7, "elbow": 1}}}))
    assert main(["evaluate", str(out), "--workspace", str(workspace)]) == 0
    assert "7 samples" in capsys.readouterr().out


def test_quiet_design_prints_nothing(tmp_path, capsys):
    out = tmp_path / "design.json"
    assert main(["design", str(write_config(tmp_path)), "--out", str(out), "--starts", "1", "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""
    assert out.is_file()


# ---------------------------------------------------------------------- bad input: exit 2, no output file
def broken_urdf(tmp_path: Path) -> dict:
    (tmp_path / "broken.urdf").write_text('<robot name="broken"><link name="a"><joint></robot>')
    return edited(mechanism={"urdf": "broken.urdf"})


CASES = {
    "unknown key": (
        lambda tmp: edited(workspace__nn=10),
        ["workspace: unknown key 'nn'; valid keys: kind, n, seed, degrees, ranges"],
    ),
    "unknown body": (
        lambda tmp: edited(springs__0__b__body="forearm"),
        ["springs[0] 's1'.b.body: unknown body 'forearm'", "bodies: universe, base, link1, link2, tool"],
    ),
    "unknown joint": (
        lambda tmp: edited(workspace__ranges={"wrist": [0, 90]}),
        ["workspace.ranges: unknown joint 'wrist'", "joints: shoulder, elbow"],
    ),
    "lower > upper": (
        lambda tmp: edited(springs__0__free_length={"lower": 1.0, "upper": 0.5}),
        ["springs[0] 's1'.free_length", "lower 1.0 > upper 0.5"],
    ),
    "nan bound": (
        lambda tmp: edited(springs__0__stiffness={"lower": 0, "upper": float("nan")}),
        ["springs[0].stiffness.upper: nan is not allowed"],
    ),
    "malformed urdf": (broken_urdf, ["mechanism.urdf: URDF file", "broken.urdf", "could not be parsed"]),
    "missing urdf": (
        lambda tmp: edited(mechanism={"urdf": "missing.urdf"}),
        ["mechanism.urdf: URDF file", "missing.urdf' does not exist"],
    ),
    "seed and seeds": (
        lambda tmp: edited(solve={"seed": 1, "seeds": [0, 1]}),
        ["solve: give seed (one) or seeds (solve at each, keep the best), not both"],
    ),
    "repeated seeds": (
        lambda tmp: edited(solve={"seeds": [2, 2]}),
        ["solve.seeds: seeds must be distinct, got [2, 2]"],
    ),
    "zero-length spring": (
        lambda tmp: edited(
            springs__0__a={"body": "universe", "point": [0, 0, 0]}, springs__0__b={"body": "link1", "point": [0, 0, 0]}
        ),
        ["spring 's1': its ends coincide (zero length)"],
    ),
}


@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_bad_config_exits_2_with_one_line_and_no_output(tmp_path, capsys, case):
    make_record, expected = CASES[case]
    config = write_config(tmp_path, make_record(tmp_path))
    out = tmp_path / "design.json"
    line = run_error(capsys, ["design", str(config), "--out", str(out)])
    assert line.startswith(f"springbalance: error: {config}: ")
    for text in expected:
        assert text in line
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".design.json")] == []


def test_missing_config_file(tmp_path, capsys):
    out = tmp_path / "design.json"
    line = run_error(capsys, ["design", str(tmp_path / "absent.yaml"), "--out", str(out)])
    assert "absent.yaml' does not exist" in line
    assert not out.exists()


def test_yaml_syntax_error(tmp_path, capsys):
    config = tmp_path / "config.yaml"
    config.write_text("mechanism: {urdf: arm.urdf\nworkspace:\n\t- x\n")
    out = tmp_path / "design.json"
    line = run_error(capsys, ["design", str(config), "--out", str(out)])
    assert "config.yaml: YAML syntax error at line" in line
    assert not out.exists()


def test_failed_design_leaves_an_existing_output_untouched(tmp_path, capsys):
    out = tmp_path / "design.json"
    out.write_text("previous design\n")
    run_error(capsys, ["design", str(write_config(tmp_path, edited(workspace__nn=1))), "--out", str(out)])
    assert out.read_text() == "previous design\n"


def test_out_is_a_directory_fails_before_solving(tmp_path, capsys):
    line = run_error(capsys, ["design", str(write_config(tmp_path)), "--out", str(tmp_path)])
    assert "is a directory" in line


def test_solver_failure_exits_1_with_statuses(tmp_path, capsys):
    # a rate of at least 5000 N/m stretched at least 5 cm pulls with at least 250 N, but max_force is 1 N:
    # infeasible, which no single bound shows (a free length the ends cannot reach is refused up front,
    # exit 2: tests/io/test_bad_input_round_two.py)
    record = edited(
        springs__0__b={"body": "link1", "point": [0.2, 0, 0]},
        springs__0__free_length=0.05,
        springs__0__stiffness={"lower": 5000, "upper": 10000},
        springs__0__max_force=1.0,
    )
    record["solve"] = {"starts": 1}
    out = tmp_path / "design.json"
    line = run_error(capsys, ["design", str(write_config(tmp_path, record)), "--out", str(out)], code=1)
    assert "no start gave a feasible design" in line and "start 0: ipopt:" in line
    assert not out.exists()
    # at several seeds: every seed named with why it found no design, and nothing saved
    line = run_error(
        capsys, ["design", str(write_config(tmp_path, record)), "--out", str(out), "--seeds", "0-1"], code=1
    )
    assert "no seed gave a feasible design: seed 0: no start gave a feasible design" in line
    assert "; seed 1: no start gave a feasible design" in line
    assert not out.exists()


def test_evaluate_errors(tmp_path, capsys):
    assert "design file" in run_error(capsys, ["evaluate", str(tmp_path / "none.json")])
    (tmp_path / "bad.json").write_text("{")
    assert "is not valid JSON" in run_error(capsys, ["evaluate", str(tmp_path / "bad.json")])


def test_evaluate_with_bad_workspace_file(tmp_path, capsys):
    out = tmp_path / "design.json"
    assert main(["design", str(write_config(tmp_path)), "--out", str(out), "--starts", "1", "--quiet"]) == 0
    workspace = tmp_path / "workspace.yaml"
    workspace.write_text(yaml.safe_dump({"workspace": {"kind": "grid", "n": {"knee": 3}}}))
    line = run_error(capsys, ["evaluate", str(out), "--workspace", str(workspace)])
    assert f"{workspace}: workspace.n: unknown joint 'knee'" in line


# ---------------------------------------------------------------------- other commands, help
def test_robots_lists_example_robot_data(capsys):
    assert main(["robots"]) == 0
    names = capsys.readouterr().out.split()
    assert "ur5" in names and "panda" in names


@pytest.mark.parametrize("argv", [[], ["design"], ["evaluate"], ["robots"]])
def test_help(capsys, argv):
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, "--help"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.startswith(f"usage: springbalance {' '.join(argv)}".rstrip())


@pytest.mark.parametrize("module", ["springbalance", "springbalance.cli"])
def test_python_dash_m_runs_the_command(module):
    completed = subprocess.run([sys.executable, "-m", module, "--version"], capture_output=True, text=True, timeout=120)
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout.startswith("springbalance ")


def test_every_command_has_a_parser_and_a_handler():
    commands = build_parser()._subparsers._group_actions[0].choices
    assert list(commands) == [
        "design",
        "evaluate",
        "clearance",
        "view",
        "report",
        "order",
        "export",
        "payload-range",
        "robots",
        "inspect",
        "explore",
        "schema",
    ]
    for name, parser in commands.items():
        assert callable(parser.get_default("handler")), name


def test_bad_option_values_are_usage_errors(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["design", str(write_config(tmp_path)), "--out", str(tmp_path / "d.json"), "--starts", "0"])
    assert exit_info.value.code == 2
    assert "--starts: must be ≥ 1" in capsys.readouterr().err
    assert not (tmp_path / "d.json").exists()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--seeds", "3-1"], "--seeds: a range of seeds goes up, got '3-1'"),
        (["--seeds", "0,x"], "--seeds: expected an integer, got 'x'"),
        (["--seeds", "0-2,1"], "--seeds: seeds must be distinct, got '0-2,1'"),
        (["--seeds", "0-99"], "--seeds: at most 64 seeds, got '0-99'"),
        (["--seeds", "0-1", "--seed", "2"], "--seed: not allowed with argument --seeds"),
    ],
)
def test_bad_seeds_are_usage_errors(tmp_path, capsys, argv, message):
    with pytest.raises(SystemExit) as exit_info:
        main(["design", str(write_config(tmp_path)), "--out", str(tmp_path / "d.json"), *argv])
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "d.json").exists()


def test_design_at_several_seeds_keeps_the_best_and_reports_each(tmp_path, capsys):
    """``--seeds 0-2,5``: four solves, the design of the lowest kept, each seed's outcome in the report and the file;
    a config's ``solve.seed`` does not apply."""
    out = tmp_path / "design.json"
    config = write_config(tmp_path, edited(solve={"starts": 2, "seed": 3}))
    assert main(["design", str(config), "--out", str(out), "--seeds", "0-2,5"]) == 0
    printed = capsys.readouterr().out
    record = json.loads(out.read_text())["solver"]
    runs = record["seeds"]["runs"]
    assert [run["seed"] for run in runs] == [0, 1, 2, 5]
    kept = min(runs, key=lambda run: run["objective"])  # they all pass here
    assert record["seeds"]["kept"] == record["seed"] == kept["seed"]
    assert f"kept the design of seed {kept['seed']}:" in printed
    for run in runs:
        assert f"seed {run['seed']}: {run['objective']:.6g} N·m, passes" in printed


# ---------------------------------------------------------------------- the installed console script
def test_console_script_error_is_one_line_without_traceback(tmp_path):
    script = Path(sys.executable).with_name("springbalance")
    assert script.is_file(), "console script not installed: pip install -e ."
    config = write_config(tmp_path, edited(springs__0__b__body="forearm"))
    out = tmp_path / "design.json"
    completed = subprocess.run(
        [str(script), "design", str(config), "--out", str(out)], capture_output=True, text=True, timeout=120
    )
    assert completed.returncode == 2
    lines = completed.stderr.splitlines()
    assert len(lines) == 1, completed.stderr
    assert lines[0].startswith("springbalance: error: ") and "unknown body 'forearm'" in lines[0]
    assert "Traceback" not in completed.stderr
    assert completed.stdout == ""
    assert not out.exists()


def test_console_script_exits_at_once_with_its_output_complete(tmp_path):
    """The console script ends with os._exit after main(): its output is flushed and complete, the exit
    handlers ran, and the status is main()'s."""
    script = Path(sys.executable).with_name("springbalance")
    config = write_config(tmp_path)
    out = tmp_path / "design.json"
    completed = subprocess.run(
        [str(script), "design", str(config), "--out", str(out)], capture_output=True, text=True, timeout=300
    )
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout.rstrip().endswith(f"design saved to {out}")
    assert json.loads(out.read_text())["design"]
    probe = (
        "import atexit, sys\nfrom springbalance import cli\n"
        "atexit.register(lambda: print('exit handler ran', flush=True))\n"
        "sys.argv = ['springbalance', 'robots']\ncli.run()\nprint('not reached')"
    )
    completed = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert completed.returncode == 0, completed.stderr
    assert "ur5" in completed.stdout and completed.stdout.rstrip().endswith("exit handler ran")
    assert "not reached" not in completed.stdout
