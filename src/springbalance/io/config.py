"""Configuration files (YAML or JSON) → a :class:`~springbalance.design.problem.DesignProblem` + solve options.

A config file is one mapping with the sections ``mechanism``, ``workspace``, ``springs``
(required) and ``objective``, ``weights``, ``solve``, ``scenarios``, ``no_joint_worse``, ``clearance`` (optional); README.md ("Config
reference") documents every key, and :mod:`springbalance.io.schema` holds the schema (pydantic
models, whose JSON Schema ``springbalance schema`` prints). A config is read in three steps:

1. the file is parsed (:mod:`springbalance.io.yaml_loader`: ``1e4`` is a number, a quoted
   ``"2e3"`` a string, a key given twice an error) and every number must be finite;
2. the record is validated against the schema (shape and types of every key);
3. the objects are built, with the checks that need the URDF (bodies and joints that exist) or
   relate values (lower ≤ upper, one of ``urdf``/``robot``, keys of a workspace kind), and the
   springs' bounds are checked against each other and the anchor regions' reach
   (:func:`springbalance.design.bounds.check_bounds`: ``min_length`` ≤ ``max_length``, ...).

Every problem is reported as a :class:`ConfigError` whose one-line message starts with the file
and the key path of the culprit, e.g. ``config.yaml: workspace: unknown key 'nn'; valid keys:
kind, n, ...``.

Units follow the rest of springbalance (m, N, N/m, rad, kg, m/s²) except where ``workspace.degrees``
is true: then joint ranges, couplings and explicit sample values of revolute joints are in
degrees. Relative file paths (URDF, sample files) are relative to the config file's folder.
"""

from __future__ import annotations

import contextlib

import csv
import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from springbalance.errors import ConfigError, InputError
from springbalance.files import read_input_text
from springbalance.io import schema
from springbalance.io.yaml_loader import MAX_BYTES, DuplicateKeyError, LimitError, load_json, load_yaml
from springbalance.model import budget
from springbalance.model.mechanism import Mechanism
from springbalance.design.clearance import Clearance
from springbalance.design.bounds import check_bounds
from springbalance.design.problem import DesignProblem
from springbalance.pipeline.run import solve
from springbalance.results.result import DesignResult
from springbalance.springs.laws import Spring
from springbalance.springs.records import spring_from_dict
from springbalance.model.workspace import Coupling, Workspace

#: top-level sections of a config file, and the keys of each record (the schema's fields).
SECTIONS = schema.SECTIONS
REQUIRED_SECTIONS = schema.REQUIRED_SECTIONS
MECHANISM_KEYS = tuple(schema.Mechanism.model_fields)
WORKSPACE_KEYS = tuple(schema.Workspace.model_fields)
WORKSPACE_KINDS = schema.WORKSPACE_KINDS
COUPLING_KEYS = tuple(schema.Coupling.model_fields)
SOLVE_KEYS = tuple(schema.Solve.model_fields)
SCENARIOS_KEYS = tuple(schema.Scenarios.model_fields)
CASE_KEYS = tuple(schema.LoadCase.model_fields)
PAYLOAD_KEYS = tuple(schema.Payload.model_fields)
PAYLOAD_RANGE_KEYS = tuple(schema.PayloadRange.model_fields)

#: which workspace keys apply to which kind (``kind`` and ``degrees`` apply to all).
_KIND_KEYS = schema.KIND_KEYS


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

    def solve(self, **overrides: Any) -> DesignResult:
        """:func:`springbalance.solve` of this config: its ``solve`` options, overridden by the ``overrides``
        that are not None."""
        return solve(self, **overrides)


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
        if record is None:
            raise ConfigError(f"{label}: empty config; expected a mapping with sections {', '.join(SECTIONS)}")
        _check_finite(record, label)
        model = schema.validated(schema.config_model(), record, label, top=True)
        base_dir = Path(base_dir)
        mechanism = _mechanism(model.mechanism, base_dir, f"{label}: mechanism")
        workspace = _workspace(mechanism, model.workspace, base_dir, f"{label}: workspace")
        springs = _springs(mechanism, record["springs"], f"{label}: springs")
        weights = _weights(mechanism, model.weights, f"{label}: weights")
        solve_options = _solve_options(model.solve)
        scenario_options = _scenarios(mechanism, model.scenarios, f"{label}: scenarios")
        clearance = (Clearance.from_dict(model.clearance.model_dump(exclude_none=True), f"{label}: clearance")
                     if model.clearance is not None else None)
        problem = DesignProblem(mechanism, workspace, springs, objective=model.objective, weights=weights,
                                no_joint_worse=model.no_joint_worse, clearance=clearance, **scenario_options)
        check_bounds(problem)  # contradictions between the springs' bounds, named before any solve
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
        if not isinstance(record, dict) or "workspace" not in record:
            found = ", ".join(map(str, record)) if isinstance(record, dict) else type(record).__name__
            raise ConfigError(f"{label}: expected a mapping with a 'workspace' key (found: {found or 'nothing'})")
        _check_finite(record, label)
        model = schema.validated(schema.WorkspaceFile, record, label, top=True)
        return _workspace(mechanism, model.workspace, path.parent, f"{label}: workspace")


def read_config_file(path: str | Path):
    """Parse a YAML or JSON file (by suffix: ``.json`` is JSON, anything else YAML).

    YAML is read by :class:`~springbalance.io.yaml_loader.ConfigLoader` (``1e4`` is a number,
    ``"2e3"`` a string); in both formats a key given twice in one mapping is an error.
    """
    path = Path(path)
    label = str(path)
    text = read_input_text(path, "config file", ConfigError, max_bytes=MAX_BYTES)
    if path.suffix.lower() == ".json":
        try:
            return load_json(text)
        except LimitError as error:
            raise ConfigError(f"{label}: {error}") from None
        except DuplicateKeyError as error:
            raise ConfigError(f"{label}: duplicate key {error.key!r} in a JSON object") from None
        except ValueError as error:  # json.JSONDecodeError
            raise ConfigError(f"{label}: JSON syntax error at line {error.lineno}, column {error.colno}: "
                              f"{error.msg}") from None
    try:
        return load_yaml(text)
    except LimitError as error:
        raise ConfigError(f"{label}: {error}") from None
    except DuplicateKeyError as error:
        raise ConfigError(f"{label}: {error.path + ': ' if error.path else ''}{error}") from None
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(error, "problem", None) or _one_line(error)
        raise ConfigError(f"{label}: YAML syntax error{where}: {problem}") from None


# ---------------------------------------------------------------------- sections
def mechanism_from_dict(record, base_dir: str | Path = ".", where: str = "mechanism") -> Mechanism:
    """``{urdf | robot, gravity?, mimic?}`` → :class:`Mechanism` (gravity [m/s²])."""
    return _mechanism(schema.validated(schema.Mechanism, record, where), base_dir, where)


def workspace_from_dict(mechanism: Mechanism, record, base_dir: str | Path = ".", where: str = "workspace") -> Workspace:
    """Build a :class:`Workspace` of ``mechanism`` from a ``workspace`` mapping (see README).

    Keys: ``kind`` (grid | sobol | random | sweep | array, default sobol), ``n``, ``seed``,
    ``degrees``, ``ranges`` [rad or m; degrees if ``degrees``], ``couplings``, ``joint`` (sweep),
    ``values`` or ``file`` (array), ``ordered`` (array). ``base_dir`` resolves a relative ``file``.
    """
    model = None if record is None else schema.validated(schema.Workspace, record, where)
    return _workspace(mechanism, model, base_dir, where)


def springs_from_list(mechanism: Mechanism, records, where: str = "springs") -> list[Spring]:
    """A list of spring records (:func:`springbalance.springs.spring_from_dict`), bodies and joints checked."""
    schema.validated(schema.spring_list_adapter(), records, where, springs_at=())
    return _springs(mechanism, records, where)


def solve_options_from_dict(record, where: str = "solve") -> dict:
    """``{starts?, seed?, method?, max_iterations?, tolerance?}`` → keyword arguments of ``solve``."""
    return _solve_options(None if record is None else schema.validated(schema.Solve, record, where))


def scenarios_from_dict(mechanism: Mechanism, record, where: str = "scenarios") -> dict:
    """``{cases | payload_range, per_scenario?, aggregate?}`` → keyword arguments of :class:`DesignProblem`.

    ``cases``: list of ``{name, payloads?: [{body, mass, point?}], mass_scale?: β | {body: β}}``;
    ``payload_range``: ``{body, point?, masses: [m1, m2, ...]}``, one scenario per mass [kg].
    """
    return _scenarios(mechanism, None if record is None else schema.validated(schema.Scenarios, record, where),
                      where)


# ---------------------------------------------------------------------- building from validated records
def _mechanism(model: schema.Mechanism, base_dir: str | Path, where: str) -> Mechanism:
    sources = [key for key in ("urdf", "robot") if getattr(model, key) is not None]
    if len(sources) != 1:
        given = f" (got {' and '.join(sources)})" if sources else ""
        raise ConfigError(f"{where}: give exactly one of 'urdf' (a file) or 'robot' (an example-robot-data name){given}")
    gravity, mimic, validate = model.gravity, model.mimic, model.validate
    if model.urdf is not None:
        urdf_path = Path(base_dir) / Path(model.urdf).expanduser()
        with _prefixed(f"{where}.urdf"):
            return Mechanism.from_urdf(urdf_path, gravity=gravity, mimic=mimic, validate=validate)
    with _prefixed(f"{where}.robot"):
        return Mechanism.from_robot(model.robot, gravity=gravity, mimic=mimic, validate=validate)


def _workspace(mechanism: Mechanism, model: schema.Workspace | None, base_dir: str | Path, where: str) -> Workspace:
    model = schema.Workspace() if model is None else model
    kind = model.kind
    for key in WORKSPACE_KEYS:
        if key in model.model_fields_set and key not in ("kind", "degrees") and key not in _KIND_KEYS[kind]:
            users = [k for k, keys in _KIND_KEYS.items() if key in keys]
            raise ConfigError(f"{where}: key {key!r} does not apply to kind {kind!r} (only to {', '.join(users)}); "
                              f"keys of {kind}: kind, degrees, {', '.join(_KIND_KEYS[kind])}")
    degrees = model.degrees
    ranges = _ranges(mechanism, model.ranges, f"{where}.ranges")
    couplings = _couplings(mechanism, model.couplings, degrees, f"{where}.couplings")
    n = model.n
    if isinstance(n, dict) and kind != "grid":
        raise ConfigError(f"{where}.n: expected an integer (a mapping joint → count is for kind grid), got {n!r}")

    with _prefixed(where):
        if kind == "grid":
            if isinstance(n, dict):
                n = dict(_joint_mapping(mechanism, n, f"{where}.n"))
            return Workspace.grid(mechanism, n=16 if n is None else n, ranges=ranges, couplings=couplings,
                                  degrees=degrees)
        if kind in ("sobol", "random"):
            constructor = Workspace.sobol if kind == "sobol" else Workspace.random
            return constructor(mechanism, n=1024 if n is None else n, ranges=ranges, couplings=couplings,
                               degrees=degrees, seed=model.seed)
        if kind == "sweep":
            if model.joint is None:
                raise ConfigError(f"{where}: kind 'sweep' needs key 'joint' (one of {', '.join(mechanism.joint_names)})")
            joint = _known_joint(mechanism, model.joint, f"{where}.joint")
            n = 181 if n is None else n
            if n < 2:
                raise ConfigError(f"{where}.n: must be ≥ 2, got {n}")
            return Workspace.sweep(mechanism, joint, n=n, ranges=ranges, degrees=degrees)
        # array
        if (model.values is None) == (model.file is None):
            raise ConfigError(f"{where}: kind 'array' needs exactly one of 'values' (rows of joint values) or 'file'")
        if model.values is not None:
            values = _value_rows(mechanism, model.values, f"{where}.values")
        else:
            values = _samples_file(mechanism, Path(base_dir) / Path(model.file).expanduser(), f"{where}.file")
        with _prefixed(f"{where}.{'values' if model.values is not None else 'file'}"):
            return Workspace.from_array(mechanism, values, ordered=model.ordered, degrees=degrees)


def _springs(mechanism: Mechanism, records: list, where: str) -> list[Spring]:
    """Springs of validated ``records`` (:func:`springbalance.springs.spring_from_dict`), bodies and joints checked."""
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


def _solve_options(model: schema.Solve | None) -> dict:
    """The keys given in the ``solve`` section (the others take the solver's defaults)."""
    if model is None:
        return {}
    return {key: getattr(model, key) for key in SOLVE_KEYS if key in model.model_fields_set}


def _scenarios(mechanism: Mechanism, model: schema.Scenarios | None, where: str) -> dict:
    from springbalance.design.scenarios import Payload, Scenario, payload_scenarios

    if model is None:
        return {}
    if (model.cases is None) == (model.payload_range is None):
        raise ConfigError(f"{where}: give exactly one of 'cases' (a list of load cases) or 'payload_range'")
    if model.cases is not None:
        scenarios = []
        for index, case in enumerate(model.cases):
            label = f"{where}.cases[{index}]"
            name = case.name if case.name is not None else f"case {index + 1}"
            items = []
            for number, payload in enumerate(case.payloads or []):
                spot = f"{label}.payloads[{number}]"
                body = _known_body(mechanism, payload.body, f"{spot}.body")
                point = [0.0, 0.0, 0.0] if payload.point is None else payload.point
                with _prefixed(spot):
                    items.append(Payload(body, payload.mass, point))
            scale = case.mass_scale
            if isinstance(scale, dict):
                scale = {_known_body(mechanism, body, f"{label}.mass_scale"): value for body, value in scale.items()}
            with _prefixed(label):
                scenarios.append(Scenario(name, items, scale))
    else:
        spec = model.payload_range
        label = f"{where}.payload_range"
        body = _known_body(mechanism, spec.body, f"{label}.body")
        point = [0.0, 0.0, 0.0] if spec.point is None else spec.point
        scenarios = payload_scenarios(body, spec.masses, point)
    return {"scenarios": scenarios, "per_scenario": model.per_scenario, "aggregate": model.aggregate}


def _known_body(mechanism: Mechanism, name, where: str) -> str:
    if not isinstance(name, str) or name not in mechanism.body_names:
        raise ConfigError(f"{where}: unknown body {name!r} in mechanism {mechanism.name!r}; "
                          f"bodies: {', '.join(mechanism.body_names)}")
    return name


# ---------------------------------------------------------------------- pieces
def _weights(mechanism: Mechanism, record: dict | None, where: str) -> dict[str, float] | None:
    """Joint weights (each ≥ 0, checked by the schema) of known joints, not all zero."""
    if record is None:
        return None
    weights = dict(_joint_mapping(mechanism, record, where))
    if weights and len(weights) == mechanism.nv and not any(weights.values()):
        raise ConfigError(f"{where}: every joint weight is zero; nothing to balance")
    return weights


def _ranges(mechanism: Mechanism, record: dict | None, where: str) -> dict[str, list[float]] | None:
    """``{joint: [lower, upper] | value}`` [rad or m, or degrees] with known joints and lower ≤ upper."""
    if record is None:
        return None
    ranges = {}
    for joint, bounds in _joint_mapping(mechanism, record, where).items():
        lower, upper = (bounds, bounds) if isinstance(bounds, float) else bounds
        if lower > upper:
            raise ConfigError(f"{where}.{joint}: lower {lower:g} > upper {upper:g}")
        ranges[joint] = [lower, upper]
    return ranges


def _couplings(mechanism: Mechanism, records: list | None, degrees: bool, where: str) -> list[Coupling]:
    if records is None:
        return []
    couplings = []
    for index, record in enumerate(records):
        label = f"{where}[{index}]"
        lower, upper = record.range
        if lower > upper:
            raise ConfigError(f"{label}.range: lower {lower:g} > upper {upper:g}")
        with _prefixed(f"{label}.expression"):
            coupling = Coupling.parse(record.expression, lower, upper, degrees=degrees)
        for joint in coupling.coefficients:
            if joint not in mechanism.joint_names:
                raise ConfigError(f"{label}.expression: unknown joint {joint!r} in {record.expression!r}; "
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
    per_byte = budget.NPY_BYTES_PER_BYTE if suffix == ".npy" else budget.CSV_BYTES_PER_BYTE
    budget.require(budget.file_bytes(path) * per_byte, f"{where}: reading samples file {str(path)!r}")
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


def _parses_as_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _check_finite(record, label: str, path: str = "") -> None:
    """Reject ``.nan`` / ``.inf`` anywhere in a parsed file, naming its key path (a rule of the whole file,
    checked before the schema)."""
    if isinstance(record, dict):
        for key, value in record.items():
            _check_finite(value, label, f"{path}.{key}" if path else str(key))
    elif isinstance(record, list):
        for index, value in enumerate(record):
            _check_finite(value, label, f"{path}[{index}]")
    elif isinstance(record, float) and not math.isfinite(record):
        raise ConfigError(f"{label}: {path or 'value'}: {record!r} is not allowed; every number must be finite")


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


