"""The config schema (pydantic models, JSON Schema) and the YAML/JSON reading rules behind it."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest

from springbalance import ConfigError
from springbalance.cli import main
from springbalance.io.config import load_config, read_config_file
from springbalance.io.schema import json_schema, schema_text
from springbalance.springs import SPRING_TYPES, TwoPointSpring

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf" / "two_link_planar.urdf"
EXAMPLES = sorted(
    path for path in (ROOT / "examples").iterdir() if path.suffix in (".yaml", ".yml", ".json")
)  # configs
COMMITTED_SCHEMA = ROOT / "docs" / "config.schema.json"

# the shoulder spring of config_helpers.SHOULDER_SPRING, as YAML text (exponents, a quoted name)
CONFIG = f"""\
mechanism: {{urdf: {URDF}, gravity: 9.81}}
workspace:
  kind: sobol
  n: 32
  degrees: true
  ranges: {{shoulder: [-90, 90], elbow: [0, 0]}}
springs:
  - name: "2e3"
    type: extension
    ideal: true
    a: {{body: universe, point: [0, 0, 0.1]}}
    b: {{body: link1, box: {{lower: [0.05, 0, 0], upper: [0.5, 0, 0]}}}}
    stiffness: {{lower: 0, upper: 1e4}}
    free_length: {{lower: 5e-2, upper: 1.0}}
weights: {{shoulder: 1.0, elbow: 0.0}}
solve: {{starts: 1, seed: 0}}
"""


def write(tmp_path: Path, text: str, name: str = "config.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def config_error(path: Path) -> str:
    with pytest.raises(ConfigError) as caught:
        load_config(path)
    message = str(caught.value)
    assert "\n" not in message and message.startswith(f"{path}: "), message
    return message


# ---------------------------------------------------------------------- the JSON Schema
@pytest.fixture(scope="module")
def schema() -> dict:
    return json_schema()


def test_schema_is_a_valid_draft_2020_12_schema(schema):
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert schema["title"] == "springbalance config" and "$id" not in schema
    assert schema["required"] == ["mechanism", "workspace", "springs"]
    assert schema["additionalProperties"] is False


@pytest.mark.parametrize("example", EXAMPLES, ids=[path.name for path in EXAMPLES])
def test_every_example_validates_against_the_schema(schema, example):
    record = read_config_file(example)
    if "explore" in record:
        # a study config (springbalance explore): a design config whose springs the study writes; each
        # task's config (with its springs) is what the schema checks
        from springbalance.explore import load_study

        study = load_study(example)
        assert study.tasks
        record = study.tasks[0].record
    jsonschema.Draft202012Validator(schema).validate(record)


def test_the_schema_rejects_what_the_loader_rejects(schema):
    validator = jsonschema.Draft202012Validator(schema)
    record = read_config_file(ROOT / "examples" / "two_link.yaml")
    assert validator.is_valid(record)
    for section, key, value in [
        ("workspace", "nn", 5),
        ("workspace", "joint", "elbow"),  # not a key of sobol
        ("mechanism", "robot", "ur5"),  # urdf and robot
        ("workspace", "kind", "halton"),
    ]:
        bad = json.loads(json.dumps(record))
        bad[section][key] = value
        assert not validator.is_valid(bad), (section, key)
    bad = json.loads(json.dumps(record))
    bad["springs"][0]["stiffness"] = "1e4"  # a quoted number is a string
    assert not validator.is_valid(bad)


def test_committed_schema_is_the_commands_output(capsys, tmp_path):
    assert main(["schema"]) == 0
    printed = capsys.readouterr().out
    assert printed == schema_text()
    assert COMMITTED_SCHEMA.read_text(encoding="utf-8") == printed, (
        "docs/config.schema.json is stale: run `springbalance schema --out docs/config.schema.json`"
    )
    out = tmp_path / "schemas" / "config.schema.json"
    assert main(["schema", "--out", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == printed
    assert json.loads(printed) == json_schema()


def test_schema_command_help_and_bad_out(capsys, tmp_path):
    with pytest.raises(SystemExit) as exit_info:
        main(["schema", "--help"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.startswith("usage: springbalance schema")
    assert main(["schema", "--out", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err


def test_spring_laws_come_from_the_registry(schema):
    members = [item["$ref"].rsplit("/", 1)[-1] for item in schema["properties"]["springs"]["items"]["oneOf"]]
    # every law of the registry, and the routed spring (a path, and one of those laws on it)
    assert members == [cls.__name__ for cls in SPRING_TYPES.values()] + ["RoutedSpring"]
    routed = schema["$defs"]["RoutedSpring"]
    assert {"path", "spring", "cable_length"} <= set(routed["required"])
    tabulated = schema["$defs"][SPRING_TYPES["tabulated"].__name__]
    assert tabulated["properties"]["type"]["const"] == "tabulated"
    assert "table" in tabulated["properties"] and "table" in tabulated["required"]
    assert {"scale", "shift", "a", "b", "stays_in_table", "mass"} <= set(tabulated["properties"])
    # the default law needs no type; every other law names its own
    assert "type" not in schema["$defs"]["ExtensionSpring"]["required"]
    assert "type" in schema["$defs"]["TorsionalSpring"]["required"]
    assert "[N/m]" in schema["$defs"]["ExtensionSpring"]["properties"]["stiffness"]["description"]


def test_a_new_law_appears_in_the_schema_without_other_edits():
    class ProbeSpring(TwoPointSpring):
        """A law defined by this test only."""

        kind = "probe_for_schema_test"
        parameter_units = {"stiffness": "N/m"}
        option_types = {**TwoPointSpring.option_types, "probe_option": bool}

        def tension(self, length, parameters):
            return parameters["stiffness"] * length

        def potential(self, length, parameters):
            return 0.5 * parameters["stiffness"] * length * length

    try:
        model = json_schema()["$defs"]["ProbeSpring"]
        assert model["properties"]["type"]["const"] == "probe_for_schema_test"
        assert model["properties"]["probe_option"]["type"] == "boolean"
    finally:
        del SPRING_TYPES["probe_for_schema_test"]
    assert "ProbeSpring" not in json_schema()["$defs"]


# ---------------------------------------------------------------------- numbers and strings
def test_quoted_name_stays_a_string_and_exponents_are_numbers(tmp_path, capsys):
    config = load_config(write(tmp_path, CONFIG))
    variables = config.problem.variables
    assert config.springs[0].name == "2e3"
    assert variables.upper[variables.names.index("2e3.stiffness")] == 1e4
    assert variables.lower[variables.names.index("2e3.free_length")] == 0.05
    out = tmp_path / "design.json"
    assert main(["design", str(tmp_path / "config.yaml"), "--out", str(out), "--quiet"]) == 0
    saved = json.loads(out.read_text())
    assert saved["springs"][0]["name"] == "2e3"


def test_unquoted_exponent_is_a_fixed_number_and_a_quoted_one_is_not(tmp_path):
    text = CONFIG.replace("stiffness: {lower: 0, upper: 1e4}", "stiffness: 1e4")
    config = load_config(write(tmp_path, text))
    assert config.springs[0].parameters["stiffness"] == 1e4
    message = config_error(write(tmp_path, CONFIG.replace("stiffness: {lower: 0, upper: 1e4}", 'stiffness: "1e4"')))
    assert message.endswith("springs[0] '2e3'.stiffness: expected a number ≥ 0 or {lower, upper, init?}, got '1e4'")
    # an unquoted exponent where a string belongs is a number, and the message says so
    message = config_error(write(tmp_path, CONFIG.replace('name: "2e3"', "name: 2e3")))
    assert message.endswith("springs[0].name: expected a string, got 2000.0")


def test_integral_floats_are_integers(tmp_path):
    config = load_config(write(tmp_path, CONFIG.replace("n: 32", "n: 3.2e1")))
    assert config.workspace.size == 32
    assert "workspace.n: expected an integer, got 32.5" in config_error(
        write(tmp_path, CONFIG.replace("n: 32", "n: 32.5"))
    )


# ---------------------------------------------------------------------- duplicate and unknown keys
def test_duplicate_top_level_key_names_the_key_and_its_lines(tmp_path):
    path = write(tmp_path, CONFIG + "workspace: {kind: grid}\n")
    line = CONFIG.count("\n") + 1
    assert config_error(path) == f"{path}: duplicate key 'workspace' at line {line} (first at line 2)"


def test_duplicate_spring_key_names_its_path_and_lines(tmp_path):
    text = CONFIG.replace("    free_length:", "    stiffness: 100\n    free_length:")
    path = write(tmp_path, text)
    lines = text.splitlines()
    first = next(i for i, line in enumerate(lines, 1) if line.strip().startswith("stiffness: {"))
    assert config_error(path) == (
        f"{path}: springs[0]: duplicate key 'stiffness' at line {first + 1} (first at line {first})"
    )


def test_duplicate_key_in_json(tmp_path):
    path = write(tmp_path, '{"mechanism": {"urdf": "a.urdf", "urdf": "b.urdf"}}', "config.json")
    assert config_error(path) == f"{path}: duplicate key 'urdf' in a JSON object"


def test_merge_keys_and_aliases_still_work(tmp_path):
    text = (
        "springs:\n"
        "  - {name: s1, a: &top {body: universe, point: [0, 0, 0.1]}}\n"
        "  - {name: s2, a: {<<: *top, point: [0, 0, 0.2]}, b: *top}\n"
    )
    springs = read_config_file(write(tmp_path, text))["springs"]
    assert springs[1]["a"] == {"body": "universe", "point": [0, 0, 0.2]}  # a key may override a merged one
    assert springs[1]["b"] == springs[0]["a"]


def test_unknown_spring_key_lists_the_valid_keys(tmp_path):
    message = config_error(write(tmp_path, CONFIG.replace("free_length:", "free_lenght:")))
    assert message.endswith(
        "springs[0] '2e3': unknown key 'free_lenght'; valid keys: name, type, a, b, stiffness, "
        "free_length, initial_tension, max_force, max_length, min_length, mass, part_number, ideal, "
        "keep_tension, max_stretch, helical"
    )


def test_errors_inside_option_records(tmp_path):
    spring = "    free_length: {lower: 5e-2, upper: 1.0}\n"
    cases = {
        "    mass: {coil_diameter: 0.02, diameter: 3}\n": "springs[0] '2e3'.mass: unknown key 'diameter'; valid keys: coil_diameter, active_coils, wire_length, "
        "material, shear_modulus, density",
        "    mass: heavy\n": "springs[0] '2e3'.mass: expected a number or a mapping, got 'heavy'",
        "    helical: {index: 3}\n": "springs[0] '2e3'.helical.index: must be ≥ 4, got 3",
        "    max_force: -1\n": "springs[0] '2e3'.max_force: must be > 0, got -1",
        "    keep_tension: yes please\n": "springs[0] '2e3'.keep_tension: expected true or false, got 'yes please'",
    }
    for option, expected in cases.items():
        message = config_error(write(tmp_path, CONFIG.replace(spring, spring + option)))
        assert message.endswith(expected), message


# ---------------------------------------------------------------------- a law found through the registry
def test_config_with_a_table_spring_loads(tmp_path):
    spring = """\
  - name: bungee
    type: tabulated
    a: {body: universe, point: [0, 0, 0.1]}
    b: {body: link1, point: [0.3, 0, 0]}
    table: [[0.1, 40], [0.2, 55], [0.3, 90], [0.45, 2e2]]
    scale: {lower: 0, upper: 5}
    shift: 0.01
    stays_in_table: false
"""
    start, end = CONFIG.index("  - name:"), CONFIG.index("weights:")
    config = load_config(write(tmp_path, CONFIG[:start] + spring + CONFIG[end:]))
    (law,) = config.springs
    assert law.kind == "tabulated" and law.name == "bungee"
    np.testing.assert_allclose(law.table[-1], [0.45, 200.0])
    assert config.problem.variables.names == ["bungee.scale"]
    short_row = spring.replace("table: [[0.1, 40], ", "table: [[0.1], ")
    message = config_error(write(tmp_path, CONFIG[:start] + short_row + CONFIG[end:]))
    assert "springs[0] 'bungee'.table[0]: expected at least 2 items, got [0.1]" in message


def test_the_solve_section_sets_the_verification_mode_and_refuses_an_unknown_one(tmp_path):
    """solve.verify: "off" skips the verification (no record), "report" keeps the record without re-solving;
    an unknown mode is a one-line error that names the key and the valid modes."""
    import springbalance as sb
    from springbalance.errors import ConfigError
    from springbalance.io.config import load_config

    text = (ROOT / "examples" / "two_link.yaml").read_text().replace("../urdf/", f"{ROOT}/urdf/")
    for mode, expect_record in (("off", False), ("report", True)):
        path = tmp_path / f"{mode}.yaml"
        path.write_text(text.replace("solve: {starts: 4, seed: 0}", f"solve: {{starts: 1, seed: 0, verify: {mode}}}"))
        config = load_config(path)
        assert config.solve_options["verify"] == mode
        result = sb.solve(config, progress=False)
        assert (result.verification is not None) == expect_record
        if expect_record:
            assert result.verification.mode == "report" and result.verification.rounds == 0
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("solve: {starts: 4, seed: 0}", "solve: {verify: always}"))
    with pytest.raises(ConfigError, match=r"verify.*always.*resolve, report, off"):
        load_config(bad)
