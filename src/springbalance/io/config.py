"""Configuration files (YAML or JSON) → a :class:`~springbalance.design.problem.DesignProblem` + solve options.

A config file is one mapping with the sections ``mechanism``, ``workspace``, ``springs``
(required) and ``objective``, ``weights``, ``solve``, ``scenarios``, ``no_joint_worse``, ``clearance``,
``max_spring_mass`` (optional); docs/guides/config.md documents every key, and :mod:`springbalance.io.schema` holds the
schema (pydantic records, whose JSON Schema ``springbalance schema`` prints). A config is read in three steps:

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

import dataclasses
import json
from pathlib import Path
from typing import Any, Mapping, cast

import yaml

from springbalance.design.bounds import check_bounds
from springbalance.design.clearance import Clearance
from springbalance.design.problem import DesignProblem
from springbalance.design.spring_mass import check_mass_bound
from springbalance.design.stock import StockPart
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.errors import ConfigError
from springbalance.files import read_input_text
from springbalance.io.config_errors import check_finite, errors_as_config_errors, one_line, prefixed
from springbalance.io.schema import (
    REQUIRED_SECTIONS,
    SECTIONS,
    WORKSPACE_KINDS,
    CouplingRecord,
    LoadCaseRecord,
    MechanismRecord,
    PayloadRangeRecord,
    PayloadRecord,
    ScenariosRecord,
    SolveRecord,
    WorkspaceFileRecord,
    WorkspaceRecord,
    config_model,
    spring_list_adapter,
    validated,
)
from springbalance.io.sections import (
    mechanism_from_record,
    scenarios_from_record,
    solve_options_from_record,
    springs_from_records,
    weights_from_record,
    workspace_from_record,
)
from springbalance.io.stock_catalogues import load_stock
from springbalance.loaders import MAX_BYTES, DuplicateKeyError, LimitError, load_json, load_yaml
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace
from springbalance.pipeline.run import solve
from springbalance.results.result import DesignResult
from springbalance.springs.laws import Spring

__all__ = [
    "CASE_KEYS",
    "COUPLING_KEYS",
    "MECHANISM_KEYS",
    "PAYLOAD_KEYS",
    "PAYLOAD_RANGE_KEYS",
    "REQUIRED_SECTIONS",
    "SCENARIOS_KEYS",
    "SECTIONS",
    "SOLVE_KEYS",
    "WORKSPACE_KEYS",
    "WORKSPACE_KINDS",
    "Config",
    "config_from_dict",
    "load_config",
    "load_workspace",
    "mechanism_from_dict",
    "read_config_file",
    "scenarios_from_dict",
    "solve_options_from_dict",
    "springs_from_list",
    "workspace_from_dict",
]

#: the keys of each record (the schema's fields); SECTIONS and REQUIRED_SECTIONS are the top-level sections.
MECHANISM_KEYS = tuple(MechanismRecord.model_fields)
WORKSPACE_KEYS = tuple(WorkspaceRecord.model_fields)
COUPLING_KEYS = tuple(CouplingRecord.model_fields)
SOLVE_KEYS = tuple(SolveRecord.model_fields)
SCENARIOS_KEYS = tuple(ScenariosRecord.model_fields)
CASE_KEYS = tuple(LoadCaseRecord.model_fields)
PAYLOAD_KEYS = tuple(PayloadRecord.model_fields)
PAYLOAD_RANGE_KEYS = tuple(PayloadRangeRecord.model_fields)


@dataclasses.dataclass
class Config:
    """A loaded configuration.

    Attributes:
        path: the config file (None when built from a mapping).
        mechanism, workspace, springs: the parts of the problem.
        problem: the :class:`~springbalance.design.problem.DesignProblem` built from them.
        solve_options: keyword arguments for :meth:`DesignProblem.solve` given in the
            ``solve`` section (only the keys present; the rest take the solver's defaults).
        stock: the stock parts that ``solve.stock`` names (:func:`~springbalance.io.stock_catalogues.load_stock`),
            which :func:`springbalance.solve` picks from when it is given no ``stock``; None without one.
        stock_source: ``solve.stock`` as written (a catalogue name, path, or several joined by commas).
    """

    path: Path | None
    mechanism: Mechanism
    workspace: Workspace
    springs: list[Spring]
    problem: DesignProblem
    solve_options: Mapping[str, Any]
    #: the ``tolerance`` section (None: grade 2 for every coil)
    tolerance: ToleranceSpec | None = None
    stock: list[StockPart] | None = None
    stock_source: str | None = None

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


def config_from_dict(
    record: Any, base_dir: str | Path = ".", label: str = "config", path: Path | None = None
) -> Config:
    """Build a :class:`Config` from an already parsed mapping.

    ``base_dir`` resolves relative file paths; ``label`` starts every error message.
    """
    with errors_as_config_errors(label):
        if record is None:
            raise ConfigError(f"{label}: empty config; expected a mapping with sections {', '.join(SECTIONS)}")
        check_finite(record, label)
        model = validated(config_model(), record, label, top=True)
        base_dir = Path(base_dir)
        mechanism = mechanism_from_record(model.mechanism, base_dir, f"{label}: mechanism")
        workspace = workspace_from_record(mechanism, model.workspace, base_dir, f"{label}: workspace")
        springs = springs_from_records(mechanism, record["springs"], f"{label}: springs")
        weights = weights_from_record(mechanism, model.weights, f"{label}: weights")
        solve_options = solve_options_from_record(model.solve)
        stock_spec = solve_options.pop("stock", None)
        with prefixed(f"{label}: solve.stock"):
            stock = None if stock_spec is None else load_stock(stock_spec, base_dir)
        scenario_options = scenarios_from_record(mechanism, model.scenarios, f"{label}: scenarios")
        clearance = (
            Clearance.from_dict(model.clearance.model_dump(exclude_none=True), f"{label}: clearance")
            if model.clearance is not None
            else None
        )
        tolerance = (
            ToleranceSpec.from_record(record["tolerance"], f"{label}: tolerance")
            if record.get("tolerance") is not None
            else None
        )
        problem = DesignProblem(
            mechanism,
            workspace,
            springs,
            objective=model.objective,
            weights=weights,
            no_joint_worse=model.no_joint_worse,
            clearance=clearance,
            max_spring_mass=model.max_spring_mass,
            **scenario_options,
            tolerance=tolerance,
        )
        check_bounds(problem)  # contradictions between the springs' bounds, named before any solve
        check_mass_bound(problem)  # a mass bound below the lightest springs the bounds allow
    source = None if stock_spec is None else stock_spec if isinstance(stock_spec, str) else ",".join(stock_spec)
    return Config(
        path, mechanism, workspace, springs, problem, solve_options, tolerance, stock=stock, stock_source=source
    )


def load_workspace(path: str | Path, mechanism: Mechanism) -> Workspace:
    """Workspace of ``mechanism`` from a YAML/JSON file holding a ``workspace:`` mapping.

    The file may be a whole config: only its ``workspace`` section is read (its other
    top-level keys must still be valid section names). Relative sample-file paths are
    relative to this file's folder.
    """
    path = Path(path)
    label = str(path)
    record = read_config_file(path)
    with errors_as_config_errors(label):
        if not isinstance(record, dict) or "workspace" not in record:
            found = ", ".join(map(str, record)) if isinstance(record, dict) else type(record).__name__
            raise ConfigError(f"{label}: expected a mapping with a 'workspace' key (found: {found or 'nothing'})")
        check_finite(record, label)
        model = validated(WorkspaceFileRecord, record, label, top=True)
        return workspace_from_record(mechanism, model.workspace, path.parent, f"{label}: workspace")


def read_config_file(path: str | Path) -> Any:
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
            syntax = cast(json.JSONDecodeError, error)
            raise ConfigError(
                f"{label}: JSON syntax error at line {syntax.lineno}, column {syntax.colno}: {syntax.msg}"
            ) from None
    try:
        return load_yaml(text)
    except LimitError as error:
        raise ConfigError(f"{label}: {error}") from None
    except DuplicateKeyError as error:
        raise ConfigError(f"{label}: {error.path + ': ' if error.path else ''}{error}") from None
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(error, "problem", None) or one_line(error)
        raise ConfigError(f"{label}: YAML syntax error{where}: {problem}") from None


# ---------------------------------------------------------------------- sections
def mechanism_from_dict(record: Any, base_dir: str | Path = ".", where: str = "mechanism") -> Mechanism:
    """``{urdf | robot, gravity?, mimic?}`` → :class:`Mechanism` (gravity [m/s²])."""
    return mechanism_from_record(validated(MechanismRecord, record, where), base_dir, where)


def workspace_from_dict(
    mechanism: Mechanism, record: Any, base_dir: str | Path = ".", where: str = "workspace"
) -> Workspace:
    """Build a :class:`Workspace` of ``mechanism`` from a ``workspace`` mapping (see docs/guides/config.md).

    Keys: ``kind`` (grid | sobol | random | sweep | array, default sobol), ``n``, ``seed``,
    ``degrees``, ``ranges`` [rad or m; degrees if ``degrees``], ``couplings``, ``joint`` (sweep),
    ``values`` or ``file`` (array), ``ordered`` (array). ``base_dir`` resolves a relative ``file``.
    """
    model = None if record is None else validated(WorkspaceRecord, record, where)
    return workspace_from_record(mechanism, model, base_dir, where)


def springs_from_list(mechanism: Mechanism, records: Any, where: str = "springs") -> list[Spring]:
    """A list of spring records (:func:`springbalance.springs.spring_from_dict`), bodies and joints checked."""
    validated(spring_list_adapter(), records, where, springs_at=())
    return springs_from_records(mechanism, records, where)


def solve_options_from_dict(record: Any, where: str = "solve") -> dict:
    """``{starts?, seed?, method?, max_iterations?, tolerance?}`` → keyword arguments of ``solve``."""
    return solve_options_from_record(None if record is None else validated(SolveRecord, record, where))


def scenarios_from_dict(mechanism: Mechanism, record: Any, where: str = "scenarios") -> dict:
    """``{cases | payload_range, per_scenario?, aggregate?}`` → keyword arguments of :class:`DesignProblem`.

    ``cases``: list of ``{name, payloads?: [{body, mass, point?}], mass_scale?: β | {body: β}}``;
    ``payload_range``: ``{body, point?, masses: [m1, m2, ...]}``, one scenario per mass [kg].
    """
    return scenarios_from_record(
        mechanism, None if record is None else validated(ScenariosRecord, record, where), where
    )
