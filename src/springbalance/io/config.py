"""Configuration files (YAML or JSON) → a :class:`~springbalance.design.problem.DesignProblem` + solve options.

A config file is one mapping with the sections ``mechanism``, ``workspace``, ``springs``
(required) and ``objective``, ``weights``, ``solve``, ``scenarios`` (optional); README.md ("Config
reference") documents every key. Every problem is reported as a :class:`ConfigError`
whose one-line message starts with the file and the key path of the culprit, e.g.
``config.yaml: workspace: unknown key 'nn'; valid keys: kind, n, ...``.

Units follow the rest of springbalance (m, N, N/m, rad) except where ``workspace.degrees``
is true: then joint ranges, couplings and explicit sample values of revolute joints are in
degrees. Relative file paths (URDF, sample files) are relative to the config file's folder.

Parsing rules worth knowing:

- Every number must be finite: ``.nan`` / ``.inf`` anywhere are rejected with their key path.
- PyYAML reads ``1e4`` and ``1.0e4`` as strings (YAML 1.1 wants ``1.0e+4``); numbers written
  in exponent form are read as numbers here.
"""

from __future__ import annotations

import contextlib

import csv
import dataclasses
import json
import math
import re
from pathlib import Path

import numpy as np
import yaml

from springbalance.errors import ConfigError, InputError
from springbalance.model.mechanism import Mechanism
from springbalance.design.objectives import OBJECTIVES
from springbalance.springs.params import check_keys
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import METHODS
from springbalance.springs.laws import Spring
from springbalance.springs.records import spring_from_dict
from springbalance.model.workspace import Coupling, Workspace

#: top-level sections of a config file.
SECTIONS = ("mechanism", "workspace", "springs", "objective", "weights", "solve", "scenarios")
REQUIRED_SECTIONS = ("mechanism", "workspace", "springs")
MECHANISM_KEYS = ("urdf", "robot", "gravity", "mimic")
WORKSPACE_KEYS = ("kind", "n", "seed", "degrees", "ranges", "couplings", "joint", "values", "file", "ordered")
WORKSPACE_KINDS = ("grid", "sobol", "random", "sweep", "array")
COUPLING_KEYS = ("expression", "range")
SOLVE_KEYS = ("starts", "seed", "method", "max_iterations", "tolerance")
SCENARIOS_KEYS = ("cases", "payload_range", "per_scenario", "aggregate")
CASE_KEYS = ("name", "payloads", "mass_scale")
PAYLOAD_KEYS = ("body", "mass", "point")
PAYLOAD_RANGE_KEYS = ("body", "point", "masses")

#: which workspace keys apply to which kind (``kind`` and ``degrees`` apply to all).
_KIND_KEYS = {
    "grid": ("n", "ranges", "couplings"),
    "sobol": ("n", "seed", "ranges", "couplings"),
    "random": ("n", "seed", "ranges", "couplings"),
    "sweep": ("n", "ranges", "joint"),
    "array": ("values", "file", "ordered"),
}
_EXPONENT_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)[eE][-+]?\d+")


@dataclasses.dataclass
class Config:
    """A loaded configuration.

    Attributes:
        path: the config file (None when built from a mapping).
        mechanism, workspace, springs: the parts of the problem.
        problem: the :class:`~springbalance.design.problem.DesignProblem` built from them.
        solve_options: keyword arguments for :meth:`DesignProblem.solve` given in the
            ``solve`` section (only the keys present; the rest take the solver's defaults).
    """

    path: Path | None
    mechanism: Mechanism
    workspace: Workspace
    springs: list[Spring]
    problem: DesignProblem
    solve_options: dict

    def solve(self, **overrides):
        """Solve the problem with the config's options, overridden by ``overrides``."""
        options = {**self.solve_options, **{k: v for k, v in overrides.items() if v is not None}}
        return self.problem.solve(**options)


# ---------------------------------------------------------------------- entry points
def load_config(path: str | Path) -> Config:
    """Read a YAML (``.yaml``/``.yml``) or JSON (``.json``) config file and build its problem.

    Raises:
        ConfigError: the file is missing, unreadable, not valid YAML/JSON, or does not match
            the schema; or the problem it describes is inconsistent (unknown body or joint,
            zero-length spring, ...). The message names the file and the key path.
    """
    path = Path(path)
    record = read_config_file(path)
    return config_from_dict(record, base_dir=path.parent, label=str(path), path=path)


def config_from_dict(record, base_dir: str | Path = ".", label: str = "config", path: Path | None = None) -> Config:
    """Build a :class:`Config` from an already parsed mapping.

    ``base_dir`` resolves relative file paths; ``label`` starts every error message.
    """
    with _errors_as_config_errors(label):
        record = _normalised(record, label)
        if record is None:
            raise ConfigError(f"{label}: empty config; expected a mapping with sections {', '.join(SECTIONS)}")
        check_keys(record, SECTIONS, label)
        for section in REQUIRED_SECTIONS:
            if section not in record:
                raise ConfigError(f"{label}: missing section {section!r} (required: {', '.join(REQUIRED_SECTIONS)})")
        base_dir = Path(base_dir)
        mechanism = mechanism_from_dict(record["mechanism"], base_dir, f"{label}: mechanism")
        workspace = workspace_from_dict(mechanism, record["workspace"], base_dir, f"{label}: workspace")
        springs = springs_from_list(mechanism, record["springs"], f"{label}: springs")
        objective = _objective(record.get("objective", "rms"), f"{label}: objective")
        weights = _weights(mechanism, record.get("weights"), f"{label}: weights")
        solve_options = solve_options_from_dict(record.get("solve"), f"{label}: solve")
        scenario_options = scenarios_from_dict(mechanism, record.get("scenarios"), f"{label}: scenarios")
        problem = DesignProblem(mechanism, workspace, springs, objective=objective, weights=weights,
                                **scenario_options)
    return Config(path, mechanism, workspace, springs, problem, solve_options)


def load_workspace(path: str | Path, mechanism: Mechanism) -> Workspace:
    """Workspace of ``mechanism`` from a YAML/JSON file holding a ``workspace:`` mapping.

    The file may be a whole config: only its ``workspace`` section is read (its other
    top-level keys must still be valid section names). Relative sample-file paths are
    relative to this file's folder.
    """
    path = Path(path)
    label = str(path)
    record = read_config_file(path)
    with _errors_as_config_errors(label):
        record = _normalised(record, label)
        if not isinstance(record, dict) or "workspace" not in record:
            found = ", ".join(map(str, record)) if isinstance(record, dict) else type(record).__name__
            raise ConfigError(f"{label}: expected a mapping with a 'workspace' key (found: {found or 'nothing'})")
        check_keys(record, SECTIONS, label)
        return workspace_from_dict(mechanism, record["workspace"], path.parent, f"{label}: workspace")


def read_config_file(path: str | Path):
    """Parse a YAML or JSON file (by suffix: ``.json`` is JSON, anything else YAML)."""
    path = Path(path)
    label = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ConfigError(f"config file {label!r} does not exist") from None
    except IsADirectoryError:
        raise ConfigError(f"config file {label!r} is a directory") from None
    except (OSError, UnicodeDecodeError) as error:
        raise ConfigError(f"config file {label!r} cannot be read: {_one_line(error)}") from None
    if path.suffix.lower() == ".json":
        try:
            return json.loads(text)
        except json.JSONDecodeError as error:
            raise ConfigError(f"{label}: JSON syntax error at line {error.lineno}, column {error.colno}: {error.msg}") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(error, "problem", None) or _one_line(error)
        raise ConfigError(f"{label}: YAML syntax error{where}: {problem}") from None


# ---------------------------------------------------------------------- sections
def mechanism_from_dict(record, base_dir: str | Path = ".", where: str = "mechanism") -> Mechanism:
    """``{urdf | robot, gravity?, mimic?}`` → :class:`Mechanism`."""
    check_keys(record, MECHANISM_KEYS, where)
    sources = [key for key in ("urdf", "robot") if key in record]
    if len(sources) != 1:
        given = f" (got {' and '.join(sources)})" if sources else ""
        raise ConfigError(f"{where}: give exactly one of 'urdf' (a file) or 'robot' (an example-robot-data name){given}")
    gravity = record.get("gravity")
    if gravity is not None:
        if _is_number(gravity):
            gravity = float(gravity)
        elif isinstance(gravity, list) and len(gravity) == 3 and all(_is_number(v) for v in gravity):
            gravity = [float(v) for v in gravity]
        else:
            raise ConfigError(f"{where}.gravity: expected a magnitude [m/s²] or a 3-vector, got {gravity!r}")
    mimic = _boolean(record.get("mimic", False), f"{where}.mimic")
    if "urdf" in record:
        urdf = _string(record["urdf"], f"{where}.urdf")
        urdf_path = Path(base_dir) / Path(urdf).expanduser()
        if not urdf_path.is_file():
            raise ConfigError(f"{where}.urdf: URDF file {str(urdf_path)!r} does not exist")
        with _prefixed(f"{where}.urdf"):
            return Mechanism.from_urdf(urdf_path, gravity=gravity, mimic=mimic)
    robot = _string(record["robot"], f"{where}.robot")
    with _prefixed(f"{where}.robot"):
        return Mechanism.from_robot(robot, gravity=gravity, mimic=mimic)


def workspace_from_dict(mechanism: Mechanism, record, base_dir: str | Path = ".", where: str = "workspace") -> Workspace:
    """Build a :class:`Workspace` of ``mechanism`` from a ``workspace`` mapping (see README).

    Keys: ``kind`` (grid | sobol | random | sweep | array, default sobol), ``n``, ``seed``,
    ``degrees``, ``ranges``, ``couplings``, ``joint`` (sweep), ``values`` or ``file``
    (array), ``ordered`` (array). ``base_dir`` resolves a relative ``file``.
    """
    record = {} if record is None else record
    check_keys(record, WORKSPACE_KEYS, where)
    kind = record.get("kind", "sobol")
    if not isinstance(kind, str) or kind not in WORKSPACE_KINDS:
        raise ConfigError(f"{where}.kind: unknown workspace kind {kind!r}; valid: {', '.join(WORKSPACE_KINDS)}")
    for key in record:
        if key not in ("kind", "degrees") and key not in _KIND_KEYS[kind]:
            users = [k for k, keys in _KIND_KEYS.items() if key in keys]
            raise ConfigError(f"{where}: key {key!r} does not apply to kind {kind!r} (only to {', '.join(users)}); "
                              f"keys of {kind}: kind, degrees, {', '.join(_KIND_KEYS[kind])}")
    degrees = _boolean(record.get("degrees", False), f"{where}.degrees")
    ranges = _ranges(mechanism, record.get("ranges"), f"{where}.ranges")
    couplings = _couplings(mechanism, record.get("couplings"), degrees, f"{where}.couplings")

    with _prefixed(where):
        if kind == "grid":
            n = record.get("n", 16)
            if isinstance(n, dict):
                n = {joint: _integer(count, f"{where}.n.{joint}", minimum=1)
                     for joint, count in _joint_mapping(mechanism, n, f"{where}.n").items()}
            else:
                n = _integer(n, f"{where}.n", minimum=1, also="or a mapping joint → count")
            return Workspace.grid(mechanism, n=n, ranges=ranges, couplings=couplings, degrees=degrees)
        if kind in ("sobol", "random"):
            n = _integer(record.get("n", 1024), f"{where}.n", minimum=1)
            seed = _integer(record.get("seed", 0), f"{where}.seed", minimum=0)
            constructor = Workspace.sobol if kind == "sobol" else Workspace.random
            return constructor(mechanism, n=n, ranges=ranges, couplings=couplings, degrees=degrees, seed=seed)
        if kind == "sweep":
            if "joint" not in record:
                raise ConfigError(f"{where}: kind 'sweep' needs key 'joint' (one of {', '.join(mechanism.joint_names)})")
            joint = _known_joint(mechanism, record["joint"], f"{where}.joint")
            n = _integer(record.get("n", 181), f"{where}.n", minimum=2)
            return Workspace.sweep(mechanism, joint, n=n, ranges=ranges, degrees=degrees)
        # array
        ordered = _boolean(record.get("ordered", True), f"{where}.ordered")
        if ("values" in record) == ("file" in record):
            raise ConfigError(f"{where}: kind 'array' needs exactly one of 'values' (rows of joint values) or 'file'")
        if "values" in record:
            values = _value_rows(mechanism, record["values"], f"{where}.values")
        else:
            values = _samples_file(mechanism, Path(base_dir) / Path(_string(record["file"], f"{where}.file")).expanduser(),
                                   f"{where}.file")
        with _prefixed(f"{where}.{'values' if 'values' in record else 'file'}"):
            return Workspace.from_array(mechanism, values, ordered=ordered, degrees=degrees)


def springs_from_list(mechanism: Mechanism, records, where: str = "springs") -> list[Spring]:
    """A list of spring records (:func:`springbalance.springs.spring_from_dict`), bodies checked."""
    if not isinstance(records, list) or not records:
        raise ConfigError(f"{where}: expected a non-empty list of springs, got {records!r}")
    springs = []
    for index, record in enumerate(records):
        label = f"{where}[{index}]"
        spring = spring_from_dict(record, label)
        name = f" {spring.name!r}" if spring.name else ""
        for end, anchor in spring.anchors.items():
            body = anchor.body
            if body not in mechanism.body_names:
                raise ConfigError(f"{label}{name}.{end}.body: unknown body {body!r} in mechanism {mechanism.name!r}; "
                                  f"bodies: {', '.join(mechanism.body_names)}")
        for joint in spring.joints:
            if joint not in mechanism.joint_names:
                raise ConfigError(f"{label}{name}.joint: unknown joint {joint!r} in mechanism {mechanism.name!r}; "
                                  f"joints: {', '.join(mechanism.joint_names)}")
        springs.append(spring)
    return springs


def solve_options_from_dict(record, where: str = "solve") -> dict:
    """``{starts?, seed?, method?, max_iterations?, tolerance?}`` → keyword arguments of ``solve``."""
    if record is None:
        return {}
    check_keys(record, SOLVE_KEYS, where)
    options = {}
    if "starts" in record:
        options["starts"] = _integer(record["starts"], f"{where}.starts", minimum=1)
    if "seed" in record:
        options["seed"] = _integer(record["seed"], f"{where}.seed", minimum=0)
    if "method" in record:
        method = record["method"]
        if not isinstance(method, str) or method not in METHODS:
            raise ConfigError(f"{where}.method: unknown method {method!r}; valid: {', '.join(METHODS)}")
        options["method"] = method
    if "max_iterations" in record:
        options["max_iterations"] = _integer(record["max_iterations"], f"{where}.max_iterations", minimum=1)
    if "tolerance" in record:
        tolerance = _number(record["tolerance"], f"{where}.tolerance")
        if tolerance <= 0:
            raise ConfigError(f"{where}.tolerance: must be > 0, got {tolerance!r}")
        options["tolerance"] = tolerance
    return options


def scenarios_from_dict(mechanism: Mechanism, record, where: str = "scenarios") -> dict:
    """``{cases | payload_range, per_scenario?, aggregate?}`` → keyword arguments of :class:`DesignProblem`.

    ``cases``: list of ``{name, payloads?: [{body, mass, point?}], mass_scale?: β | {body: β}}``;
    ``payload_range``: ``{body, point?, masses: [m1, m2, ...]}``, one scenario per mass [kg].
    """
    from springbalance.design.problem import AGGREGATES
    from springbalance.design.scenarios import Payload, Scenario, payload_scenarios

    if record is None:
        return {}
    check_keys(record, SCENARIOS_KEYS, where)
    if ("cases" in record) == ("payload_range" in record):
        raise ConfigError(f"{where}: give exactly one of 'cases' (a list of load cases) or 'payload_range'")
    if "cases" in record:
        cases = record["cases"]
        if not isinstance(cases, list) or not cases:
            raise ConfigError(f"{where}.cases: expected a non-empty list of cases, got {cases!r}")
        scenarios = []
        for index, case in enumerate(cases):
            label = f"{where}.cases[{index}]"
            check_keys(case, CASE_KEYS, label)
            name = _string(case.get("name", f"case {index + 1}"), f"{label}.name")
            payloads = case.get("payloads", [])
            if not isinstance(payloads, list):
                raise ConfigError(f"{label}.payloads: expected a list of {{body, mass, point}}, got {payloads!r}")
            items = []
            for number, payload in enumerate(payloads):
                spot = f"{label}.payloads[{number}]"
                check_keys(payload, PAYLOAD_KEYS, spot)
                for key in ("body", "mass"):
                    if key not in payload:
                        raise ConfigError(f"{spot}: missing key {key!r}")
                body = _known_body(mechanism, payload["body"], f"{spot}.body")
                point = _vector(payload.get("point", [0.0, 0.0, 0.0]), f"{spot}.point")
                with _prefixed(spot):
                    items.append(Payload(body, _number(payload["mass"], f"{spot}.mass"), point))
            scale = case.get("mass_scale")
            if isinstance(scale, dict):
                scale = {_known_body(mechanism, body, f"{label}.mass_scale"): _number(value, f"{label}.mass_scale.{body}")
                         for body, value in scale.items()}
            elif scale is not None:
                scale = _number(scale, f"{label}.mass_scale")
            with _prefixed(label):
                scenarios.append(Scenario(name, items, scale))
    else:
        spec = record["payload_range"]
        label = f"{where}.payload_range"
        check_keys(spec, PAYLOAD_RANGE_KEYS, label)
        for key in ("body", "masses"):
            if key not in spec:
                raise ConfigError(f"{label}: missing key {key!r}")
        body = _known_body(mechanism, spec["body"], f"{label}.body")
        masses = spec["masses"]
        if not isinstance(masses, list) or not masses or not all(_is_number(m) and m >= 0 for m in masses):
            raise ConfigError(f"{label}.masses: expected a non-empty list of masses ≥ 0 [kg], got {masses!r}")
        scenarios = payload_scenarios(body, masses, _vector(spec.get("point", [0.0, 0.0, 0.0]), f"{label}.point"))
    per_scenario = record.get("per_scenario", [])
    if not isinstance(per_scenario, list) or not all(isinstance(name, str) and name for name in per_scenario):
        raise ConfigError(f"{where}.per_scenario: expected a list of variable names (e.g. [s1.b]), got {per_scenario!r}")
    aggregate = record.get("aggregate", "sum")
    if aggregate not in AGGREGATES:
        raise ConfigError(f"{where}.aggregate: unknown aggregate {aggregate!r}; valid: {', '.join(AGGREGATES)}")
    return {"scenarios": scenarios, "per_scenario": per_scenario, "aggregate": aggregate}


def _known_body(mechanism: Mechanism, name, where: str) -> str:
    if not isinstance(name, str) or name not in mechanism.body_names:
        raise ConfigError(f"{where}: unknown body {name!r} in mechanism {mechanism.name!r}; "
                          f"bodies: {', '.join(mechanism.body_names)}")
    return name


def _vector(value, where: str) -> list[float]:
    if not isinstance(value, list) or len(value) != 3 or not all(_is_number(v) for v in value):
        raise ConfigError(f"{where}: expected three numbers [m], got {value!r}")
    return [float(v) for v in value]


# ---------------------------------------------------------------------- pieces
def _objective(value, where: str) -> str:
    if not isinstance(value, str) or value not in OBJECTIVES:
        raise ConfigError(f"{where}: unknown objective {value!r}; valid: {', '.join(OBJECTIVES)}")
    return value


def _weights(mechanism: Mechanism, record, where: str) -> dict[str, float] | None:
    if record is None:
        return None
    weights = {}
    for joint, value in _joint_mapping(mechanism, record, where).items():
        weight = _number(value, f"{where}.{joint}")
        if weight < 0:
            raise ConfigError(f"{where}.{joint}: a weight must be ≥ 0, got {weight!r}")
        weights[joint] = weight
    if weights and len(weights) == mechanism.nv and not any(weights.values()):
        raise ConfigError(f"{where}: every joint weight is zero; nothing to balance")
    return weights


def _ranges(mechanism: Mechanism, record, where: str) -> dict[str, list[float]] | None:
    if record is None:
        return None
    ranges = {}
    for joint, bounds in _joint_mapping(mechanism, record, where).items():
        label = f"{where}.{joint}"
        if _is_number(bounds):
            bounds = [bounds, bounds]
        lower, upper = _pair(bounds, label, "[lower, upper] or a single value")
        if lower > upper:
            raise ConfigError(f"{label}: lower {lower:g} > upper {upper:g}")
        ranges[joint] = [lower, upper]
    return ranges


def _couplings(mechanism: Mechanism, records, degrees: bool, where: str) -> list[Coupling]:
    if records is None:
        return []
    if not isinstance(records, list):
        raise ConfigError(f"{where}: expected a list of {{expression, range}} mappings, got {records!r}")
    couplings = []
    for index, record in enumerate(records):
        label = f"{where}[{index}]"
        check_keys(record, COUPLING_KEYS, label)
        for key in COUPLING_KEYS:
            if key not in record:
                raise ConfigError(f"{label}: missing key {key!r}")
        expression = _string(record["expression"], f"{label}.expression")
        lower, upper = _pair(record["range"], f"{label}.range", "[lower, upper]")
        if lower > upper:
            raise ConfigError(f"{label}.range: lower {lower:g} > upper {upper:g}")
        with _prefixed(f"{label}.expression"):
            coupling = Coupling.parse(expression, lower, upper, degrees=degrees)
        for joint in coupling.coefficients:
            if joint not in mechanism.joint_names:
                raise ConfigError(f"{label}.expression: unknown joint {joint!r} in {expression!r}; "
                                  f"joints: {', '.join(mechanism.joint_names)}")
        couplings.append(coupling)
    return couplings


def _value_rows(mechanism: Mechanism, values, where: str) -> np.ndarray:
    shape = f"a list of rows of {mechanism.nv} numbers ({', '.join(mechanism.joint_names)})"
    if not isinstance(values, list) or not values:
        raise ConfigError(f"{where}: expected {shape}, got {values!r}")
    if mechanism.nv == 1 and all(_is_number(v) for v in values):
        return np.array(values, dtype=float)[:, None]
    for index, row in enumerate(values):
        if not isinstance(row, list) or len(row) != mechanism.nv or not all(_is_number(v) for v in row):
            raise ConfigError(f"{where}[{index}]: expected {mechanism.nv} numbers ({', '.join(mechanism.joint_names)}), "
                              f"got {row!r}")
    return np.array(values, dtype=float)


def _samples_file(mechanism: Mechanism, path: Path, where: str) -> np.ndarray:
    """Samples from ``.npy`` (N×nv array) or ``.csv`` (optional header of joint names)."""
    if not path.is_file():
        raise ConfigError(f"{where}: samples file {str(path)!r} does not exist")
    suffix = path.suffix.lower()
    if suffix == ".npy":
        try:
            values = np.load(path, allow_pickle=False)
        except (OSError, ValueError) as error:
            raise ConfigError(f"{where}: cannot read {str(path)!r} as a NumPy array: {_one_line(error)}") from None
        if values.ndim == 1 and mechanism.nv == 1:
            values = values[:, None]
        try:
            values = np.asarray(values, dtype=float)
        except (TypeError, ValueError):
            raise ConfigError(f"{where}: {str(path)!r} does not hold numbers (dtype {values.dtype})") from None
        if not np.all(np.isfinite(values)):
            raise ConfigError(f"{where}: {str(path)!r} holds values that are not finite numbers")
        return values
    if suffix != ".csv":
        raise ConfigError(f"{where}: samples file {str(path)!r} must end in .csv or .npy")
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as error:
        raise ConfigError(f"{where}: cannot read {str(path)!r}: {_one_line(error)}") from None
    numbered = [(number, line) for number, line in enumerate(lines, start=1)
                if line.strip() and not line.lstrip().startswith("#")]
    if not numbered:
        raise ConfigError(f"{where}: {str(path)!r} holds no samples")
    rows = list(csv.reader(line for _, line in numbered))
    columns, width = list(range(mechanism.nv)), mechanism.nv
    if not all(_parses_as_float(cell) for cell in rows[0]):
        names = [cell.strip() for cell in rows[0]]
        unknown = [name for name in names if name not in mechanism.joint_names]
        missing = [name for name in mechanism.joint_names if name not in names]
        if unknown or missing or len(names) != len(set(names)):
            raise ConfigError(f"{where}: header of {str(path)!r} must name each joint once "
                              f"({', '.join(mechanism.joint_names)}), got {', '.join(names)}")
        columns, width = [names.index(name) for name in mechanism.joint_names], len(names)
        rows, numbered = rows[1:], numbered[1:]
    values = []
    for (number, _), row in zip(numbered, rows):
        if len(row) != width:
            raise ConfigError(f"{where}: {str(path)!r} line {number}: expected {mechanism.nv} values "
                              f"({', '.join(mechanism.joint_names)}), got {len(row)}")
        try:
            numbers = [float(row[column]) for column in columns]
        except ValueError:
            raise ConfigError(f"{where}: {str(path)!r} line {number}: not a number in {row!r}") from None
        if not all(math.isfinite(v) for v in numbers):
            raise ConfigError(f"{where}: {str(path)!r} line {number}: values must be finite, got {row!r}")
        values.append(numbers)
    if not values:
        raise ConfigError(f"{where}: {str(path)!r} holds no samples")
    return np.array(values)


# ---------------------------------------------------------------------- scalar checks
def _joint_mapping(mechanism: Mechanism, record, where: str) -> dict:
    if not isinstance(record, dict):
        raise ConfigError(f"{where}: expected a mapping joint name → value, got {record!r}")
    mapping = {}
    for joint, value in record.items():
        mapping[_known_joint(mechanism, joint, where)] = value
    return mapping


def _known_joint(mechanism: Mechanism, name, where: str) -> str:
    name = str(name)
    if name not in mechanism.joint_names:
        raise ConfigError(f"{where}: unknown joint {name!r} in mechanism {mechanism.name!r}; "
                          f"joints: {', '.join(mechanism.joint_names)}")
    return name


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _number(value, where: str) -> float:
    if not _is_number(value):
        raise ConfigError(f"{where}: expected a number, got {value!r}")
    return float(value)


def _integer(value, where: str, minimum: int | None = None, also: str = "") -> int:
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if not isinstance(value, int) or isinstance(value, bool):
        raise ConfigError(f"{where}: expected an integer{' ' + also if also else ''}, got {value!r}")
    if minimum is not None and value < minimum:
        raise ConfigError(f"{where}: must be ≥ {minimum}, got {value}")
    return value


def _boolean(value, where: str) -> bool:
    if not isinstance(value, bool):
        raise ConfigError(f"{where}: expected true or false, got {value!r}")
    return value


def _string(value, where: str) -> str:
    if not isinstance(value, str) or not value:
        raise ConfigError(f"{where}: expected a non-empty string, got {value!r}")
    return value


def _pair(value, where: str, expected: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2 or not all(_is_number(v) for v in value):
        raise ConfigError(f"{where}: expected {expected} (numbers), got {value!r}")
    return float(value[0]), float(value[1])


def _parses_as_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _normalised(record, label: str, path: str = ""):
    """Copy of ``record`` with exponent-form strings read as numbers; non-finite numbers rejected."""
    if isinstance(record, dict):
        return {key: _normalised(value, label, f"{path}.{key}" if path else str(key)) for key, value in record.items()}
    if isinstance(record, list):
        return [_normalised(value, label, f"{path}[{index}]") for index, value in enumerate(record)]
    if isinstance(record, str) and _EXPONENT_NUMBER.fullmatch(record.strip()):
        record = float(record)
    if isinstance(record, float) and not math.isfinite(record):
        raise ConfigError(f"{label}: {path or 'value'}: {record!r} is not allowed; every number must be finite")
    return record


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).split()) or type(error).__name__


@contextlib.contextmanager
def _prefixed(where: str, config_errors: bool = False):
    """Re-raise an :class:`InputError` of the library as a one-line :class:`ConfigError` that starts
    with ``where`` (the config key path). ConfigErrors raised inside pass unchanged, unless
    ``config_errors`` (the file-level guard): then they too get ``where`` in front when they lack it."""
    try:
        yield
    except ConfigError as error:
        if not config_errors or str(error).startswith(where):
            raise
        raise ConfigError(f"{where}: {_one_line(error)}") from None
    except InputError as error:
        message = _one_line(error)
        if config_errors and message.startswith(where):
            raise ConfigError(message) from None
        raise ConfigError(f"{where}: {message}") from None


def _errors_as_config_errors(label: str):
    """Every :class:`InputError` leaves as a one-line :class:`ConfigError` that starts with ``label``."""
    return _prefixed(label, config_errors=True)


