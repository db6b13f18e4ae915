"""Config files (YAML/JSON) → DesignProblem + solve options, and their one-line errors."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from config_helpers import SHOULDER_SPRING, edited_record
from springbalance import ConfigError, InputError
from springbalance.io.config import WORKSPACE_KEYS, config_from_dict, load_config, load_workspace, workspace_from_dict
from springbalance.model.mechanism import Mechanism

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf" / "two_link_planar.urdf"
EXAMPLE = ROOT / "examples" / "two_link.yaml"

BASE = {
    "mechanism": {"urdf": str(URDF), "gravity": 9.81},
    "workspace": {
        "kind": "sobol",
        "n": 32,
        "seed": 0,
        "degrees": True,
        "ranges": {"shoulder": [-90, 90], "elbow": [0, 0]},
    },
    "springs": [SHOULDER_SPRING],
    "objective": "rms",
    "weights": {"shoulder": 1.0, "elbow": 0.0},
    "solve": {"starts": 2, "seed": 3, "method": "auto", "max_iterations": 200},
}


def write(tmp_path: Path, record, name: str = "config.yaml") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(record) if name.endswith(".json") else yaml.safe_dump(record, sort_keys=False))
    return path


def config_error(tmp_path: Path, record, name: str = "config.yaml") -> str:
    """Load ``record`` as a config file, expect a ConfigError, return its message."""
    path = write(tmp_path, record, name)
    with pytest.raises(ConfigError) as caught:
        load_config(path)
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: "), message
    return message


def edited(**changes) -> dict:
    """A deep copy of BASE with ``section__key=value`` changes (value None deletes the key)."""
    return edited_record(BASE, **changes)


# ---------------------------------------------------------------------- valid configs
def test_base_config_builds_problem_and_solve_options(tmp_path):
    config = load_config(write(tmp_path, BASE))
    problem = config.problem
    assert problem.workspace.size == 32
    assert problem.objective.name == "rms"
    assert [spring.name for spring in problem.springs] == ["s1"]
    assert problem.variables.names == ["s1.b.x", "s1.stiffness", "s1.free_length"]
    assert config.solve_options == {"starts": 2, "seed": 3, "method": "auto", "max_iterations": 200}
    np.testing.assert_allclose(config.mechanism.gravity, [0, 0, -9.81])
    np.testing.assert_allclose(problem.weights, [1.0, 0.0])
    # degrees: the shoulder range [-90°, 90°] is stored in radians; the elbow is held at 0.
    shoulder, elbow = problem.workspace.joint_values.T
    assert shoulder.min() >= -math.pi / 2 and shoulder.max() <= math.pi / 2 and shoulder.max() > 1.0
    assert np.all(elbow == 0)


def test_example_config_is_valid():
    config = load_config(EXAMPLE)
    assert config.workspace.size == 128
    assert config.problem.objective.name == "rms"
    assert len(config.springs) == 3 and all(spring.kind == "extension" for spring in config.springs)
    assert all(spring.max_outer_diameter == 0.04 and spring.ideal is False for spring in config.springs)
    assert config.solve_options["starts"] == 4


def test_json_config_and_optional_sections(tmp_path):
    record = edited(objective=None, weights=None, solve=None)
    config = load_config(write(tmp_path, record, "config.json"))
    assert config.problem.objective.name == "rms"
    assert config.solve_options == {}
    np.testing.assert_allclose(config.problem.weights, [1.0, 1.0])


def test_relative_urdf_path_is_relative_to_the_config_folder(tmp_path, monkeypatch):
    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "arm.urdf").write_text(URDF.read_text())
    (tmp_path / "configs").mkdir()
    path = write(tmp_path / "configs", edited(mechanism={"urdf": "../robots/arm.urdf"}))
    monkeypatch.chdir(tmp_path / "robots")  # somewhere else
    config = load_config(path)
    assert config.mechanism.source["path"] == str((tmp_path / "robots" / "arm.urdf").resolve())


def test_exponent_numbers_are_numbers(tmp_path):
    # PyYAML reads 1e4 and 1.0e4 as strings; the config reads them as numbers.
    text = yaml.safe_dump(BASE, sort_keys=False).replace("upper: 10000", "upper: 1e4")
    assert "upper: 1e4" in text
    path = tmp_path / "config.yaml"
    path.write_text(text)
    config = load_config(path)
    assert config.problem.variables.upper[config.problem.variables.names.index("s1.stiffness")] == 1e4


def test_gravity_vector(tmp_path):
    config = load_config(write(tmp_path, edited(mechanism__gravity=[0, 0, -9.8])))
    np.testing.assert_allclose(config.mechanism.gravity, [0, 0, -9.8])


def test_unknown_robot(tmp_path):
    message = config_error(tmp_path, edited(mechanism={"robot": "pnda"}))
    assert "mechanism.robot: unknown example-robot-data robot 'pnda'; did you mean 'panda'?" in message
    assert "`springbalance robots`" in message
    assert "ur5" not in message  # a suggestion, not the whole list of names


# ---------------------------------------------------------------------- workspaces
@pytest.fixture(scope="module")
def mechanism():
    return Mechanism.from_urdf(URDF)


def test_grid_with_counts_per_joint(mechanism):
    workspace = workspace_from_dict(mechanism, {"kind": "grid", "n": {"shoulder": 5, "elbow": 3}})
    assert workspace.size == 15 and workspace.ordered


def test_couplings_in_degrees_filter_samples(mechanism):
    workspace = workspace_from_dict(
        mechanism,
        {
            "kind": "random",
            "n": 200,
            "seed": 1,
            "degrees": True,
            "couplings": [{"expression": "elbow - shoulder", "range": [-60, 0]}],
        },
    )
    difference = np.rad2deg(workspace.joint_values[:, 1] - workspace.joint_values[:, 0])
    assert workspace.size == 200
    assert difference.min() >= -60 - 1e-9 and difference.max() <= 1e-9


def test_sweep(mechanism):
    workspace = workspace_from_dict(
        mechanism,
        {"kind": "sweep", "joint": "elbow", "n": 7, "degrees": True, "ranges": {"elbow": [-30, 30], "shoulder": 10}},
    )
    np.testing.assert_allclose(np.rad2deg(workspace.joint_values[:, 1]), np.linspace(-30, 30, 7))
    np.testing.assert_allclose(np.rad2deg(workspace.joint_values[:, 0]), 10)


def test_array_values_in_degrees(mechanism):
    workspace = workspace_from_dict(mechanism, {"kind": "array", "degrees": True, "values": [[0, 90], [180, -90]]})
    np.testing.assert_allclose(workspace.joint_values, [[0, np.pi / 2], [np.pi, -np.pi / 2]])
    assert workspace.ordered


def test_array_from_csv_with_header_in_any_column_order(mechanism, tmp_path):
    (tmp_path / "samples.csv").write_text("# trajectory\nelbow,shoulder\n0.5,0.1\n0.25,0.2\n")
    workspace = workspace_from_dict(mechanism, {"kind": "array", "file": "samples.csv", "ordered": False}, tmp_path)
    np.testing.assert_allclose(workspace.joint_values, [[0.1, 0.5], [0.2, 0.25]])
    assert not workspace.ordered


def test_array_from_npy(mechanism, tmp_path):
    np.save(tmp_path / "samples.npy", np.array([[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]]))
    workspace = workspace_from_dict(mechanism, {"kind": "array", "file": "samples.npy"}, tmp_path)
    assert workspace.size == 3 and workspace.joint_values[2, 1] == 0.6


def test_load_workspace_from_workspace_file_or_full_config(mechanism, tmp_path):
    only = write(tmp_path, {"workspace": {"kind": "grid", "n": 4}}, "workspace.yaml")
    assert load_workspace(only, mechanism).size == 16
    full = write(tmp_path, BASE, "full.yaml")
    assert load_workspace(full, mechanism).size == 32
    bare = write(tmp_path, {"kind": "grid", "n": 4}, "bare.yaml")
    with pytest.raises(ConfigError, match=r"bare\.yaml: expected a mapping with a 'workspace' key"):
        load_workspace(bare, mechanism)


# ---------------------------------------------------------------------- errors
def test_unknown_key_names_the_path_and_lists_valid_keys(tmp_path):
    message = config_error(tmp_path, edited(workspace__nn=5))
    assert message.endswith(f"workspace: unknown key 'nn'; valid keys: {', '.join(WORKSPACE_KEYS)}")


def test_unknown_top_level_and_spring_keys(tmp_path):
    assert "unknown key 'solver'; valid keys: mechanism, workspace, springs, objective, weights, solve" in config_error(
        tmp_path, edited(solver={"starts": 2})
    )
    message = config_error(tmp_path, edited(springs__0__b__box__uper=[0.5, 0, 0]))
    assert "springs[0] 's1'.b.box: unknown key 'uper'; valid keys: lower, upper, init" in message
    assert "solve: unknown key 'restarts'" in config_error(tmp_path, edited(solve__restarts=3))


def test_unknown_body(tmp_path):
    message = config_error(tmp_path, edited(springs__0__b__body="forearm"))
    assert "springs[0] 's1'.b.body: unknown body 'forearm'" in message
    assert "bodies: universe, base, link1, link2, tool" in message


def test_unknown_joint_in_ranges_and_weights(tmp_path):
    message = config_error(tmp_path, edited(workspace__ranges={"wrist": [0, 1]}))
    assert "workspace.ranges: unknown joint 'wrist'" in message and "joints: shoulder, elbow" in message
    assert "weights: unknown joint 'knee'" in config_error(tmp_path, edited(weights={"knee": 1.0}))


def test_lower_above_upper(tmp_path):
    message = config_error(tmp_path, edited(workspace__ranges={"shoulder": [90, -90]}))
    assert message.endswith("workspace.ranges.shoulder: lower 90 > upper -90")
    message = config_error(tmp_path, edited(springs__0__stiffness={"lower": 100, "upper": 10}))
    assert "springs[0] 's1'.stiffness" in message and "lower 100.0 > upper 10.0" in message


def test_nan_is_rejected_with_its_key_path(tmp_path):
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(BASE, sort_keys=False).replace("upper: 10000", "upper: .nan"))
    with pytest.raises(ConfigError) as caught:
        load_config(path)
    assert str(caught.value) == f"{path}: springs[0].stiffness.upper: nan is not allowed; every number must be finite"


def test_wrong_types(tmp_path):
    assert "workspace.n: expected an integer" in config_error(tmp_path, edited(workspace__n="many"))
    assert "workspace.degrees: expected true or false, got 'yes please'" in config_error(
        tmp_path, edited(workspace__degrees="yes please")
    )
    assert "solve.starts: must be ≥ 1, got 0" in config_error(tmp_path, edited(solve__starts=0))
    assert "objective: unknown objective 'rmse'; valid: rms, peak, pe_variance, energy" in config_error(
        tmp_path, edited(objective="rmse")
    )
    assert "springs: expected a non-empty list of springs" in config_error(tmp_path, edited(springs=[]))
    assert "springs[0].type: unknown spring type ['extension']" in config_error(
        tmp_path, edited(springs__0__type=["extension"])
    )


@pytest.mark.parametrize(
    ("spring", "message"),
    [
        (
            {"type": "gas", "a": SHOULDER_SPRING["a"], "b": SHOULDER_SPRING["b"], "free_length": 0.3},
            "springs[0] 's1': missing key 'stiffness': the gas spring's rate k [N/m], "
            "a number (fixed) or {lower, upper} (a design variable)",
        ),
        (
            {"type": "torsional", "joint": "elbow", "stiffness": 5.0},
            "springs[0] 's1': missing key 'neutral_angle': the torsional spring's neutral angle q0 [rad], "
            "a number (fixed) or {lower, upper} (a design variable)",
        ),
    ],
    ids=["gas-without-rate", "torsional-without-neutral-angle"],
)
def test_a_missing_parameter_is_named_with_its_meaning_unit_and_form(tmp_path, spring, message):
    assert config_error(tmp_path, edited(springs=[{"name": "s1", **spring}])).endswith(message)


def test_key_of_another_workspace_kind(tmp_path):
    message = config_error(tmp_path, edited(workspace__joint="shoulder"))
    assert "workspace: key 'joint' does not apply to kind 'sobol' (only to sweep)" in message


def test_missing_section_and_source(tmp_path):
    assert "missing section 'springs' (required: mechanism, workspace, springs)" in config_error(
        tmp_path, edited(springs=None)
    )
    message = config_error(tmp_path, edited(mechanism={"urdf": str(URDF), "robot": "ur5"}))
    assert "mechanism: give exactly one of 'urdf'" in message and "(got urdf and robot)" in message


def test_missing_and_malformed_urdf(tmp_path):
    message = config_error(tmp_path, edited(mechanism={"urdf": "nowhere.urdf"}))
    assert "mechanism.urdf: URDF file" in message and "nowhere.urdf" in message and "does not exist" in message
    (tmp_path / "broken.urdf").write_text('<robot name="broken"><link name="a"></robot>')
    message = config_error(tmp_path, edited(mechanism={"urdf": "broken.urdf"}))
    assert "mechanism.urdf:" in message and "could not be parsed" in message


def test_zero_length_spring(tmp_path):
    record = edited(
        springs__0__a={"body": "universe", "point": [0, 0, 0]}, springs__0__b={"body": "link1", "point": [0, 0, 0]}
    )
    assert "spring 's1': its ends coincide (zero length)" in config_error(tmp_path, record)


def test_missing_file_and_syntax_errors(tmp_path):
    with pytest.raises(ConfigError, match="config file .*absent.yaml' does not exist"):
        load_config(tmp_path / "absent.yaml")
    path = tmp_path / "config.yaml"
    path.write_text("mechanism: {urdf: arm.urdf\nworkspace: {}\n")
    with pytest.raises(ConfigError, match=r"config\.yaml: YAML syntax error at line \d+, column \d+"):
        load_config(path)
    path = tmp_path / "config.json"
    path.write_text('{"mechanism": }')
    with pytest.raises(ConfigError, match=r"config\.json: JSON syntax error at line 1, column 15"):
        load_config(path)


def test_errors_are_input_errors_for_dict_configs():
    with pytest.raises(InputError, match=r"^config: workspace.kind: unknown workspace kind 'halton'"):
        config_from_dict(edited(workspace__kind="halton"))


def test_yaml_booleans_are_those_of_yaml_1_2_so_an_anchor_key_on_stays_a_key():
    # YAML 1.1 (PyYAML's default) reads on/off/yes/no as booleans: `on: floor` would become {True: 'floor'}
    from springbalance.loaders import load_yaml

    record = load_yaml("a: {body: universe, on: floor}\nflags: [yes, no, off, true, false, True]\n")
    assert record["a"] == {"body": "universe", "on": "floor"}
    assert record["flags"] == ["yes", "no", "off", True, False, True]
