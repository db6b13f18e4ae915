"""Bad input, round two (issue 15): impossible arms, resource exhaustion, hostile YAML, damaged designs.

Every case goes through the command line and must end with exit status 2 (1 for a solver failure),
one line on stderr that names the culprit, no traceback, no file left behind and an existing
``--out`` unchanged. The resource cases also run in a subprocess under a hard memory limit
(``RLIMIT_AS``, 1 GiB), where they must be refused cleanly within 5 s.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yaml

from config_helpers import SHOULDER_SPRING, edited_record
from springbalance.cli import main
from springbalance.errors import InputError
from springbalance.io import config as config_io
from springbalance.loaders import MAX_BYTES, MAX_DEPTH, LimitError, load_json, load_yaml
from springbalance.model import budget
from springbalance.model.mechanism import Mechanism
from springbalance.model.robots import available_robots
from springbalance.model.workspace import Workspace

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf" / "two_link_planar.urdf"
SENTINEL = "an earlier design, to be left alone\n"

BASE = {
    "mechanism": {"urdf": str(URDF)},
    "workspace": {
        "kind": "sobol",
        "n": 16,
        "seed": 0,
        "degrees": True,
        "ranges": {"shoulder": [-90, 90], "elbow": [0, 0]},
    },
    "springs": [SHOULDER_SPRING],
    "weights": {"elbow": 0.0},
    "solve": {"starts": 1, "seed": 0},
}


def edited(**changes) -> dict:
    return edited_record(BASE, **changes)


def write_config(folder: Path, record, name: str = "config.yaml") -> Path:
    path = folder / name
    path.write_text(json.dumps(record) if name.endswith(".json") else yaml.safe_dump(record, sort_keys=False))
    return path


def urdf_with(folder: Path, old: str, new: str, name: str = "arm.urdf") -> Path:
    """The two-link URDF with the first ``old`` replaced by ``new``."""
    text = URDF.read_text()
    assert old in text, old
    path = folder / name
    path.write_text(text.replace(old, new, 1))
    return path


def run_error(capsys, argv, code: int = 2) -> str:
    """``main(argv)`` exits with ``code``, prints nothing on stdout and one error line (no traceback) on
    stderr; returns that line."""
    assert main(argv) == code
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("springbalance: error: "), lines[0]
    assert "Traceback" not in captured.err
    assert captured.out == ""
    return lines[0]


def design_fails(tmp_path, capsys, record, *expected, code: int = 2, name: str = "config.yaml") -> str:
    """``design`` of ``record`` fails naming ``expected``; a new --out is not written, an existing one is
    unchanged, and no other file appears."""
    config = record if isinstance(record, Path) else write_config(tmp_path, record, name)
    new_out = tmp_path / "new" / "design.json"
    existing = tmp_path / "existing.json"
    existing.write_text(SENTINEL)
    before = sorted(path.name for path in tmp_path.rglob("*"))
    line = run_error(capsys, ["design", str(config), "--out", str(new_out)], code)
    for text in expected:
        assert text in line, line
    run_error(capsys, ["design", str(config), "--out", str(existing)], code)
    assert existing.read_text() == SENTINEL
    assert not new_out.exists()
    assert sorted(path.name for path in tmp_path.rglob("*")) == before  # no partial or temporary file
    return line


@pytest.fixture(scope="module")
def design_file(tmp_path_factory) -> Path:
    """A small saved design of the two-link arm."""
    folder = tmp_path_factory.mktemp("design")
    out = folder / "design.json"
    assert main(["design", str(write_config(folder, BASE)), "--out", str(out), "--quiet"]) == 0
    return out


# ---------------------------------------------------------------------- physically impossible arms
IMPOSSIBLE = {
    "negative mass": (('<mass value="2.0"/>', '<mass value="-2"/>'), ["link 'link1'", "<mass value='-2'> is negative"]),
    "nan mass": (('<mass value="2.0"/>', '<mass value="nan"/>'), ["link 'link1'", "<mass> value='nan'"]),
    "infinite mass": (('<mass value="2.0"/>', '<mass value="inf"/>'), ["link 'link1'", "<mass> value='inf'"]),
    "negative ixx": (('ixx="0.0005"', 'ixx="-1"'), ["link 'link1'", "inertia ixx=-1 is negative"]),
    "triangle inequality": (
        ('iyy="0.042"', 'iyy="0.01"'),
        ["link 'link1'", "iyy=0.01", "izz=0.042", "violates the triangle inequality"],
    ),
    "lower > upper": (
        ('lower="-1.5707963267948966"', 'lower="2"'),
        ["joint 'shoulder'", "<limit lower='2' upper='1.5707963267948966'>: lower > upper"],
    ),
    "zero axis": (('<axis xyz="0 -1 0"/>', '<axis xyz="0 0 0"/>'), ["joint 'shoulder'", "<axis xyz='0 0 0'>"]),
}


@pytest.mark.parametrize("case", IMPOSSIBLE, ids=list(IMPOSSIBLE))
def test_impossible_urdf_is_refused_naming_link_or_joint_and_attribute(tmp_path, capsys, case):
    (old, new), expected = IMPOSSIBLE[case]
    urdf = urdf_with(tmp_path, old, new)
    line = design_fails(tmp_path, capsys, edited(mechanism={"urdf": str(urdf)}), "mechanism.urdf", *expected)
    assert str(urdf) in line
    inspect = run_error(capsys, ["inspect", str(urdf)])
    assert all(text in inspect for text in expected)


@pytest.mark.parametrize("case", ["negative mass", "negative ixx", "triangle inequality", "lower > upper"])
def test_the_opt_out_loads_a_deliberately_odd_arm(tmp_path, capsys, case):
    (old, new), _ = IMPOSSIBLE[case]
    urdf = urdf_with(tmp_path, old, new)
    assert "validate=False" in run_error(capsys, ["inspect", str(urdf)])  # the message says how to opt out
    assert main(["inspect", str(urdf), "--no-validate", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["source"]["validate"] is False
    mechanism = Mechanism.from_urdf(urdf, validate=False)
    assert mechanism.nv == 2 and mechanism.source["validate"] is False
    config = config_io.config_from_dict(edited(mechanism={"urdf": str(urdf), "validate": False}))
    assert config.mechanism.source["validate"] is False
    if case == "negative mass":
        assert summary["bodies"][2]["mass"] == -2.0


def test_the_opt_out_is_saved_with_the_design(tmp_path, capsys):
    urdf = urdf_with(tmp_path, 'iyy="0.042"', 'iyy="0.01"')  # an inertia that breaks the triangle inequality
    out = tmp_path / "design.json"
    config = write_config(tmp_path, edited(mechanism={"urdf": str(urdf), "validate": False}))
    assert main(["design", str(config), "--out", str(out), "--quiet"]) == 0
    assert json.loads(out.read_text())["mechanism"]["validate"] is False
    assert main(["evaluate", str(out)]) == 0  # rebuilt without the checks, as it was designed
    exported = tmp_path / "balanced.urdf"
    assert main(["export", str(out), "--urdf", str(exported)]) == 0  # and it reads back the same way
    assert exported.is_file()
    capsys.readouterr()


def test_malformed_numbers_are_named_even_with_the_opt_out(tmp_path, capsys):
    urdf = urdf_with(tmp_path, 'lower="-1.5707963267948966"', 'lower="nan"')
    line = run_error(capsys, ["inspect", str(urdf), "--no-validate"])
    assert "joint 'shoulder': <limit> lower='nan' is not a finite number" in line
    assert "valid URDF model" not in line
    urdf = urdf_with(tmp_path, '<origin xyz="0.5 0 0" rpy="0 0 0"/>', '<origin xyz="0.5 0" rpy="0 0 0"/>')
    assert "joint 'elbow': <origin> xyz='0.5 0' is not 3 finite numbers" in run_error(capsys, ["inspect", str(urdf)])
    with pytest.raises(InputError, match=r"link 'link1': <mass> value='nan'"):
        Mechanism.from_urdf_string(
            URDF.read_text().replace('<mass value="2.0"/>', '<mass value="nan"/>'), validate=False
        )


def test_a_pinocchio_model_with_a_negative_mass_is_refused():
    model = Mechanism.from_urdf(URDF).model
    model.inertias[1] = pin.Inertia(-1.0, np.zeros(3), np.eye(3) * 1e-3)
    with pytest.raises(InputError, match=r"body of joint 'shoulder': mass -1 is negative"):
        Mechanism.from_model(model)
    assert Mechanism.from_model(model, validate=False).model.inertias[1].mass == -1.0


def test_massless_links_the_urdf_means_stay_allowed(tmp_path):
    # base has no <inertial>; a massless tool link with mass 0 and a zero inertia; a point mass (zero inertia)
    text = (
        URDF.read_text()
        .replace(
            '<mass value="0.5"/>\n      <inertia ixx="0.0001" ixy="0" ixz="0" iyy="0.0001" iyz="0" izz="0.0001"/>',
            '<mass value="0"/>\n      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>',
        )
        .replace(
            'ixx="0.0003" ixy="0" ixz="0" iyy="0.0135" iyz="0" izz="0.0135"',
            'ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"',
        )
    )
    mechanism = Mechanism.from_urdf_string(text)
    masses = {body["name"]: body["mass"] for body in mechanism.summary()["bodies"]}
    assert masses["base"] == 0.0 and masses["tool"] == 0.0 and masses["link2"] == 1.0


@pytest.mark.filterwarnings("ignore:.*declares mimic joints")
@pytest.mark.parametrize("urdf", sorted((ROOT / "urdf").glob("*.urdf")), ids=lambda path: path.name)
def test_every_shipped_urdf_loads_with_the_checks(urdf):
    assert Mechanism.from_urdf(urdf).nv >= 1


@pytest.mark.filterwarnings("ignore:.*declares mimic joints")
@pytest.mark.parametrize(
    "robot",
    [
        "ur5",
        "ur3",
        "ur10",
        "panda",
        "talos_arm",
        "solo",
        "solo12",
        "kinova",
        "z1",
        "xarm7",
        "so100",
        "so101",
        "double_pendulum",
        "double_pendulum_continuous",
        "finger_edu",
        "asr_twodof",
    ],
)
def test_example_robot_data_arms_load_with_the_checks(robot):
    if robot not in available_robots():
        pytest.fail(f"example-robot-data lacks {robot!r}")
    assert Mechanism.from_robot(robot).nv >= 1


# ---------------------------------------------------------------------- misleading messages
def test_a_urdf_path_that_is_a_directory_says_so(tmp_path, capsys):
    folder = tmp_path / "arm.urdf"
    folder.mkdir()
    line = design_fails(tmp_path, capsys, edited(mechanism={"urdf": str(folder)}), "mechanism.urdf", "is a directory")
    assert "does not exist" not in line


def test_an_unreadable_urdf_says_permission_denied(tmp_path, capsys, monkeypatch):
    urdf = tmp_path / "locked.urdf"
    urdf.write_text(URDF.read_text())
    urdf.chmod(0)
    if os.geteuid() == 0:  # root reads any file: make the read fail the way it fails for everybody else
        real = Path.read_bytes

        def read_bytes(self):
            if self == urdf:
                raise PermissionError(13, "Permission denied", str(self))
            return real(self)

        monkeypatch.setattr(Path, "read_bytes", read_bytes)
    line = design_fails(
        tmp_path,
        capsys,
        edited(mechanism={"urdf": str(urdf)}),
        "mechanism.urdf",
        "locked.urdf' cannot be read: permission denied",
    )
    assert "valid URDF model" not in line


# ---------------------------------------------------------------------- resources
RESOURCE_CASES = {
    "sobol 1e8": ("design", {"workspace__n": 100_000_000}, "a sobol workspace of 100000000 samples"),
    "n 1e20": ("design", {"workspace__n": 1.0e20}, "a sobol workspace of 100000000000000000000 samples"),
    "sweep 1e9": (
        "design",
        {"workspace": {"kind": "sweep", "joint": "shoulder", "n": 1_000_000_000}},
        "a sweep of 1000000000 samples",
    ),
    "grid 100000": (
        "design",
        {"workspace": {"kind": "grid", "n": 100_000}},
        "a grid workspace of 100000 × 100000 = 10000000000 samples",
    ),
    "evaluate --workspace 1e8": (
        "evaluate",
        {"workspace": {"kind": "sobol", "n": 100_000_000}},
        "a sobol workspace of 100000000 samples",
    ),
    "alias bomb": ("design", None, "expands to more than"),
    "Workspace.sobol(n=10**12)": ("python", None, "a sobol workspace of 1000000000000 samples"),
}

ALIAS_BOMB = "a: &a [1, 2, 3, 4, 5, 6, 7, 8, 9]\n" + "".join(
    f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 9)}]\n" for i in range(8)
)

CHILD = textwrap.dedent("""
    import json, resource, sys, time
    limit = int(sys.argv[1])
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    from springbalance.cli import main
    argv = json.loads(sys.argv[2])
    start = time.perf_counter()
    if argv == ["python"]:
        from springbalance.errors import InputError
        from springbalance.model.mechanism import Mechanism
        from springbalance.model.workspace import Workspace
        try:
            Workspace.sobol(Mechanism.from_urdf(sys.argv[3]), n=10**12)
            code = 0
        except InputError as error:
            print(f"springbalance: error: {error}", file=sys.stderr)
            code = 2
    else:
        code = main(argv)
    print(json.dumps({"code": code, "seconds": time.perf_counter() - start}))
""")


def resource_argv(tmp_path: Path, case: str, design: Path) -> list[str]:
    command, changes, _ = RESOURCE_CASES[case]
    if command == "python":
        return ["python"]
    if case == "alias bomb":
        config = tmp_path / "bomb.yaml"
        config.write_text(ALIAS_BOMB + yaml.safe_dump(BASE, sort_keys=False))
    elif command == "evaluate":
        config = write_config(tmp_path, changes, "workspace.yaml")
        return ["evaluate", str(design), "--workspace", str(config)]
    else:
        config = write_config(tmp_path, edited(**changes))
    return ["design", str(config), "--out", str(tmp_path / "design.json")]


@pytest.mark.parametrize("case", RESOURCE_CASES, ids=list(RESOURCE_CASES))
def test_resource_exhaustion_is_refused_under_a_hard_memory_limit(tmp_path, design_file, case):
    limit = 1 << 30  # 1 GiB of address space
    argv = resource_argv(tmp_path, case, design_file)
    environment = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    environment.pop(budget.ENV, None)  # the default limit: half the memory available (here: under the rlimit)
    completed = subprocess.run(
        [sys.executable, "-c", CHILD, str(limit), json.dumps(argv), str(URDF)],
        capture_output=True,
        text=True,
        timeout=120,
        env=environment,
        cwd=tmp_path,
    )
    assert "Traceback" not in completed.stderr and "MemoryError" not in completed.stderr, completed.stderr
    report = json.loads(completed.stdout.splitlines()[-1])
    assert report["code"] == 2, completed.stderr
    lines = completed.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("springbalance: error: "), completed.stderr
    assert RESOURCE_CASES[case][2] in lines[0]
    if case != "alias bomb":
        assert "of memory (estimate)" in lines[0] and "--max-memory" in lines[0]
    assert report["seconds"] < 5.0
    assert not (tmp_path / "design.json").exists()


def test_max_memory_option_and_environment_variable(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv(budget.ENV, "1M")
    config = write_config(tmp_path, edited(workspace__n=100_000))
    out = tmp_path / "out.json"
    line = run_error(capsys, ["design", str(config), "--out", str(out)])
    assert "more than the limit of 1 MiB (SPRINGBALANCE_MAX_MEMORY)" in line
    line = run_error(capsys, ["design", str(config), "--out", str(out), "--max-memory", "2M"])
    assert "more than the limit of 2 MiB (--max-memory)" in line
    line = run_error(capsys, ["--max-memory", "3MiB", "design", str(config), "--out", str(out)])
    assert "more than the limit of 3 MiB (--max-memory)" in line
    assert "--max-memory: expected a size" in run_error(
        capsys, ["design", str(config), "--out", str(out), "--max-memory", "lots"]
    )
    monkeypatch.setenv(budget.ENV, "-5")
    assert "environment variable SPRINGBALANCE_MAX_MEMORY: expected a size" in run_error(
        capsys, ["design", str(config), "--out", str(out)]
    )
    assert not out.exists()


def test_the_default_limit_is_half_the_available_memory(monkeypatch):
    monkeypatch.delenv(budget.ENV, raising=False)
    assert (budget.available_memory() or 0) > 0  # read off this machine (/proc/meminfo)
    # the machine's available memory moves between two readings (a shared machine): hold it for the rule
    monkeypatch.setattr(budget, "available_memory", lambda: 6 << 30)
    limit, source = budget.current_limit()
    assert source == "half the available memory"
    assert limit == 3 << 30
    assert budget.parse_size("2G") == 2 << 30 and budget.parse_size("512MiB") == 512 << 20
    assert budget.parse_size("1.5e9") == 1_500_000_000 and budget.parse_size("unlimited") is None


def test_python_api_refuses_huge_workspaces_with_input_error():
    mechanism = Mechanism.from_urdf(URDF)
    with pytest.raises(InputError, match=r"sobol workspace of 1000000000000 samples .* of memory \(estimate\)"):
        Workspace.sobol(mechanism, n=10**12)
    with pytest.raises(InputError, match=r"must be an integer ≥ 1, got inf"):
        Workspace.random(mechanism, n=float("inf"))
    with pytest.raises(InputError, match=r"a sweep of 10000000000 samples"):
        Workspace.sweep(mechanism, "shoulder", n=10**10)
    with budget.memory_limit("1M"):
        with pytest.raises(InputError, match=r"limit of 1 MiB"):
            Workspace.grid(mechanism, n=300)


def test_a_scene_of_too_many_frames_is_refused(tmp_path, capsys, design_file):
    out = tmp_path / "report"
    line = run_error(capsys, ["report", str(design_file), "--out", str(out), "--frames", "1000000000"])
    assert "a scene of 1000000001 frames (--frames 1000000000 per moving joint)" in line
    assert not out.exists()
    assert "--frames 1000000000" in run_error(capsys, ["view", str(design_file), "--frames", "1000000000"])


def test_a_huge_samples_file_is_refused_before_reading(tmp_path, capsys, monkeypatch):
    samples = tmp_path / "samples.csv"
    samples.write_text("shoulder,elbow\n" + "0.1,0.0\n" * 20_000)
    monkeypatch.setenv(budget.ENV, "64k")
    record = edited(workspace={"kind": "array", "file": "samples.csv"})
    line = design_fails(tmp_path, capsys, record, "workspace.file: reading samples file", "limit of 64 KiB")
    assert "samples.csv" in line


# ---------------------------------------------------------------------- hostile YAML and JSON
def test_yaml_alias_bomb_deep_nesting_and_recursion_are_refused(tmp_path, capsys):
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text(ALIAS_BOMB + yaml.safe_dump(BASE, sort_keys=False))
    assert "the document expands to more than 2000000 values" in design_fails(tmp_path, capsys, bomb)
    deep = tmp_path / "deep.yaml"
    deep.write_text("mechanism: " + "[" * 100_000 + "]" * 100_000 + "\n")
    assert f"nested more than {MAX_DEPTH} levels deep at line 1" in design_fails(tmp_path, capsys, deep)
    recursive = tmp_path / "recursive.yaml"
    recursive.write_text("mechanism: &m {urdf: x, self: *m}\n")
    assert "a recursive alias at line 1" in design_fails(tmp_path, capsys, recursive)
    with pytest.raises(LimitError):
        load_yaml("[" * 70 + "]" * 70)
    assert load_yaml("a: &x [1, 2]\nb: *x\n") == {"a": [1, 2], "b": [1, 2]}  # plain aliases still work


def test_json_deep_nesting_and_oversized_files_are_refused(tmp_path, capsys):
    deep = tmp_path / "deep.json"
    deep.write_text('{"mechanism": ' + "[" * 100_000 + "]" * 100_000 + "}")
    assert "nested more than 64 levels deep" in design_fails(tmp_path, capsys, deep)
    with pytest.raises(LimitError):
        load_json("[" * 70 + "]" * 70)
    big = tmp_path / "big.yaml"
    big.write_text(yaml.safe_dump(BASE) + "#" + "x" * MAX_BYTES + "\n")
    assert "is larger than 16 MiB" in design_fails(tmp_path, capsys, big)


@pytest.mark.parametrize(
    "name, text, expected",
    [
        ("config.yaml", "mechanism: {urdf: a.urdf}\nmechanism: {robot: ur5}\n", "duplicate key 'mechanism' at line 2"),
        ("config.yaml", "solve:\n  starts: 1\n  starts: 2\n", "solve: duplicate key 'starts' at line 3"),
        (
            "config.json",
            '{"mechanism": {"robot": "ur5"}, "mechanism": {"robot": "panda"}}',
            "duplicate key 'mechanism' in a JSON object",
        ),
    ],
)
def test_duplicate_keys_are_refused(tmp_path, capsys, name, text, expected):
    config = tmp_path / name
    config.write_text(text)
    assert expected in design_fails(tmp_path, capsys, config)


# ---------------------------------------------------------------------- contradictions between bounds
def spring(**options) -> dict:
    return {**SHOULDER_SPRING, **options}


CONTRADICTIONS = {
    "min_length > max_length": (
        spring(min_length=2.0, max_length=1.0),
        ["spring 's1': min_length 2 m > max_length 1 m"],
    ),
    "initial tension above max_force": (
        spring(initial_tension={"lower": 50, "upper": 60}, max_force=20),
        ["initial_tension is at least 50 N, above max_force 20 N"],
    ),
    "max_length the anchors never reach": (spring(max_length=0.01), ["max_length 0.01 m", "at least 0.149"]),
    "min_length the anchors never reach": (spring(min_length=5.0), ["min_length 5 m", "at most"]),
    "free length the anchors cannot reach": (
        spring(b={"body": "link1", "point": [0.2, 0, 0]}, free_length=1.0),
        ["free_length [1, 1] m", "keep_tension", "allow a free length of at most 0.10"],
    ),
    "constant force above max_force": (
        {
            "name": "f",
            "type": "constant_force",
            "a": {"body": "universe", "point": [0, 0, 0.1]},
            "b": {"body": "link1", "point": [0.3, 0, 0]},
            "force": {"lower": 40, "upper": 50},
            "max_force": 10,
        },
        ["spring 'f': force is at least 40 N, above max_force 10 N"],
    ),
}


@pytest.mark.parametrize("case", CONTRADICTIONS, ids=list(CONTRADICTIONS))
def test_contradictions_between_bounds_are_named_before_solving(tmp_path, capsys, case):
    record, expected = CONTRADICTIONS[case]
    line = design_fails(tmp_path, capsys, edited(springs=[record]), *expected)
    assert "no start gave a feasible design" not in line


def test_a_real_solver_failure_still_exits_1(tmp_path, capsys):
    record = edited(
        springs=[
            spring(
                b={"body": "link1", "point": [0.2, 0, 0]},
                free_length=0.05,
                stiffness={"lower": 5000, "upper": 10000},
                max_force=1.0,
            )
        ]
    )
    assert "no start gave a feasible design" in design_fails(tmp_path, capsys, record, code=1)


# ---------------------------------------------------------------------- damaged design files
def damaged(design: Path, folder: Path, change) -> Path:
    record = json.loads(design.read_text())
    change(record)
    path = folder / "damaged.json"
    path.write_text(json.dumps(record))
    return path


def first_variable(record) -> str:
    return next(iter(record["variables"]))


DAMAGE = {
    "workspace as a list": (lambda r: r.update(workspace=[1, 2]), "workspace: expected a mapping, got [1, 2]"),
    "variable 'x'": (
        lambda r: r["variables"].update({first_variable(r): "x"}),
        "variables.s1.b.x: expected a finite number, got 'x'",
    ),
    "nan variable": (
        lambda r: r["variables"].update({first_variable(r): float("nan")}),
        "variables.s1.b.x: expected a finite number, got nan",
    ),
    "ragged samples": (
        lambda r: r["workspace"]["joint_values"][1].append(0.0),
        "workspace.joint_values[1]: 3 values, the rows before have 2",
    ),
    "infinite sample": (
        lambda r: r["workspace"]["joint_values"][0].__setitem__(0, float("inf")),
        "workspace.joint_values[0]: expected a row of finite numbers",
    ),
    "negative weight": (
        lambda r: r["weights"].update(elbow=-1),
        "weights.elbow: expected a finite number from 0 to 1e+12",
    ),
    "unknown mechanism kind": (lambda r: r["mechanism"].update(kind="mystery"), "mechanism.kind: expected one of"),
    "springs not a list": (lambda r: r.update(springs={"s1": {}}), "springs: expected a non-empty list"),
    "missing variables": (lambda r: r.pop("variables"), "lacks key 'variables'"),
    "another mechanism": (
        lambda r: r["mechanism"].update(path=str(ROOT / "urdf" / "single_link_r1.urdf")),
        "this design was made for a different mechanism (joints shoulder, elbow); mechanism 'single_link_r1'",
    ),
    "huge variable": (
        lambda r: r["variables"].update({first_variable(r): 1e300}),
        "variables.s1.b.x: 1e+300 is beyond ±1e+12 (SI units)",
    ),
    "huge joint value": (
        lambda r: r["workspace"]["joint_values"][0].__setitem__(1, 1e300),
        "workspace sample 0 has a joint value beyond ±1e+06 rad or m",
    ),
    "huge anchor": (
        lambda r: r["springs"][0]["a"].update(point=[0, 0, 1e300]),
        "spring 's1': anchor a has a coordinate of 1e+300 m in the frame of 'universe'",
    ),
    "huge gravity": (lambda r: r["mechanism"].update(gravity=1e300), "gravity 1e+300 is beyond 1000 m/s²"),
    "a body of another arm": (
        lambda r: r["springs"][0]["b"].update(body="forearm"),
        "springs[0].b.body: this design was made for a different mechanism: body 'forearm'",
    ),
}


@pytest.mark.parametrize("case", DAMAGE, ids=list(DAMAGE))
def test_damaged_design_files_are_named(tmp_path, capsys, design_file, case):
    change, expected = DAMAGE[case]
    path = damaged(design_file, tmp_path, change)
    assert expected in run_error(capsys, ["evaluate", str(path)])
    report = tmp_path / "report"
    assert expected in run_error(capsys, ["report", str(path), "--out", str(report)])
    assert not report.exists()
    existing = tmp_path / "existing.xml"
    existing.write_text(SENTINEL)
    assert expected in run_error(capsys, ["export", str(path), "--mjcf", str(existing)])
    assert existing.read_text() == SENTINEL


def test_duplicate_key_in_a_design_file(tmp_path, capsys, design_file):
    text = design_file.read_text().replace('"objective":', '"objective": "peak", "objective":', 1)
    (tmp_path / "twice.json").write_text(text)
    assert "duplicate key 'objective' in a JSON object" in run_error(capsys, ["evaluate", str(tmp_path / "twice.json")])


# ---------------------------------------------------------------------- payload-range
@pytest.mark.parametrize(
    "argv, expected",
    [
        (["--masses", "nan"], "payload mass nan kg"),
        (["--masses", "1", "-1"], "payload mass -1 kg"),
        (["--masses", "inf"], "payload mass inf kg"),
        (["--point", "1e9", "0", "0"], "is 1e+09 m from the origin of 'link2'"),
        (["--point", "nan", "0", "0"], "payload point must be three finite numbers"),
    ],
)
def test_payload_range_refuses_impossible_masses_and_points(tmp_path, capsys, design_file, argv, expected):
    plot = tmp_path / "plot"
    line = run_error(capsys, ["payload-range", str(design_file), "--body", "link2", *argv, "--plot", str(plot)])
    assert expected in line
    assert not list(tmp_path.iterdir())
