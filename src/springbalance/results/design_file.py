"""Checks of a saved design file (``design.json``) before it is used.

:meth:`springbalance.results.result.DesignResult.load` reads a design file in three steps:

1. :func:`read_design_record`: the file is JSON (a key given twice is an error), not larger than
   the memory budget allows (:mod:`springbalance.model.budget`), and a springbalance design;
2. :func:`check_design_record`: every key it uses has the right type, and every number that
   enters the evaluation is finite: the mechanism source, the workspace samples (rows of equal
   length) [rad or m], the objective, the joint weights (≥ 0), the spring records and the design
   variables [SI];
3. :func:`check_design_mechanism`: the record fits the mechanism it is evaluated on: the joint
   names (the keys of ``weights``) and the width of the samples are those of the mechanism, and
   every spring's bodies and joints exist. A design made for another URDF is reported as such,
   with both lists of joints, rather than as an array-shape mismatch.

Every problem is one :class:`~springbalance.errors.InputError` naming the file and the key path.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from springbalance.errors import InputError
from springbalance.files import read_input_text
from springbalance.loaders import DuplicateKeyError, LimitError, load_json
from springbalance.model import budget
from springbalance.model.mechanism import Mechanism

FORMAT = "springbalance-design/1"
#: a design file's parsed record takes about this many times its size in memory
MEMORY_PER_BYTE = 12
#: the largest magnitude of a design variable or weight (SI units): beyond it the torques overflow
MAX_VALUE = 1e12
_SOURCE_KINDS = {"robot": "robot", "urdf": "path", "urdf_string": "text"}


def read_design_record(path: str | Path) -> dict[str, Any]:
    """The record of the design file ``path`` (parsed, format checked; see the module documentation)."""
    path = Path(path)
    label = f"design file {str(path)!r}"
    budget.require(budget.file_bytes(path) * MEMORY_PER_BYTE, f"reading {label}")
    text = read_input_text(path, "design file", InputError)
    try:
        record = load_json(text)
    except DuplicateKeyError as error:
        raise InputError(f"{label}: duplicate key {error.key!r} in a JSON object") from None
    except LimitError as error:
        raise InputError(f"{label}: {error}") from None
    except ValueError as error:  # json.JSONDecodeError
        raise InputError(f"{label} is not valid JSON: {error}") from None
    if not isinstance(record, dict) or record.get("format") != FORMAT:
        raise InputError(f"{label} is not a springbalance design (format {FORMAT!r})")
    return record


def check_design_record(record: dict[str, Any], label: str) -> None:
    """Types and finite numbers of the keys :meth:`DesignResult.load` uses; ``label`` starts the message."""
    for key in ("mechanism", "workspace", "objective", "weights", "springs", "variables"):
        if key not in record:
            raise InputError(f"{label} lacks key {key!r}")
    _check_mechanism_source(record["mechanism"], label)
    _check_workspace(record["workspace"], label)
    if not isinstance(record["objective"], str):
        raise InputError(f"{label}: objective: expected a name, got {_shown(record['objective'])}")
    _check_weights_springs_variables(record, label)
    _check_solver(record.get("solver", {}), label)
    if "partial" in record and not isinstance(record["partial"], bool):
        raise InputError(f"{label}: partial: expected true or false, got {_shown(record['partial'])}")
    if "partial_reason" in record and not isinstance(record["partial_reason"], str):
        raise InputError(f"{label}: partial_reason: expected a string, got {_shown(record['partial_reason'])}")
    for key in ("scenarios", "clearance"):
        if record.get(key) is not None:
            _mapping(record[key], f"{label}: {key}")
    _check_scenarios(record.get("scenarios"), label)
    bound = record.get("max_spring_mass")
    if bound is not None and not (_is_number(bound) and 0 < bound <= MAX_VALUE):
        raise InputError(f"{label}: max_spring_mass: expected a finite number > 0 [kg], got {_shown(bound)}")


def _check_mechanism_source(value: Any, label: str) -> None:
    """The record's ``mechanism``: a saved source (robot, URDF path or URDF text), gravity [m/s²], flags."""
    source = _mapping(value, f"{label}: mechanism")
    kind = source.get("kind")
    if not isinstance(kind, str) or kind not in _SOURCE_KINDS:
        raise InputError(
            f"{label}: mechanism.kind: expected one of {', '.join(_SOURCE_KINDS)}, got {kind!r} "
            "(a bare Pinocchio model is not saved)"
        )
    needed = _SOURCE_KINDS[kind]
    if not isinstance(source.get(needed), str) or not source[needed]:
        raise InputError(f"{label}: mechanism.{needed}: expected a non-empty string, got {source.get(needed)!r}")
    if kind == "robot" and source.get("path") is not None and not isinstance(source["path"], str):
        raise InputError(f"{label}: mechanism.path: expected a string, got {source['path']!r}")
    gravity = source.get("gravity")
    if gravity is not None and not (
        _is_number(gravity) or (isinstance(gravity, list) and len(gravity) == 3 and all(_is_number(v) for v in gravity))
    ):
        raise InputError(
            f"{label}: mechanism.gravity: expected a finite magnitude or three finite numbers [m/s²], "
            f"got {_shown(gravity)}"
        )
    for key in ("mimic", "validate"):
        if key in source and not isinstance(source[key], bool):
            raise InputError(f"{label}: mechanism.{key}: expected true or false, got {_shown(source[key])}")


def _check_workspace(value: Any, label: str) -> None:
    """The record's ``workspace``: rows of equal length of finite joint values [rad or m], ``ordered``, and
    a ``description``."""
    workspace = _mapping(value, f"{label}: workspace")
    rows = workspace.get("joint_values")
    where = f"{label}: workspace.joint_values"
    if not isinstance(rows, list) or not rows:
        raise InputError(f"{where}: expected a non-empty list of rows of joint values, got {_shown(rows)}")
    width = None
    for index, row in enumerate(rows):
        if not isinstance(row, list) or not row or not all(_is_number(v) for v in row):
            raise InputError(f"{where}[{index}]: expected a row of finite numbers [rad or m], got {_shown(row)}")
        if width is not None and len(row) != width:
            raise InputError(f"{where}[{index}]: {len(row)} values, the rows before have {width}")
        width = len(row)
    if not isinstance(workspace.get("ordered"), bool):
        raise InputError(f"{label}: workspace.ordered: expected true or false, got {_shown(workspace.get('ordered'))}")
    _mapping(workspace.get("description"), f"{label}: workspace.description")


def _check_weights_springs_variables(record: dict[str, Any], label: str) -> None:
    """The record's joint ``weights`` (finite, 0 … MAX_VALUE), ``springs`` (a non-empty list of records) and
    design ``variables`` (finite, within ±MAX_VALUE in SI units)."""
    weights = _mapping(record["weights"], f"{label}: weights")
    for joint, weight in weights.items():
        if not _is_number(weight) or not 0 <= weight <= MAX_VALUE:
            raise InputError(
                f"{label}: weights.{joint}: expected a finite number from 0 to {MAX_VALUE:g}, got {_shown(weight)}"
            )
    springs = record["springs"]
    if not isinstance(springs, list) or not springs:
        raise InputError(f"{label}: springs: expected a non-empty list of spring records, got {_shown(springs)}")
    for index, spring in enumerate(springs):
        _mapping(spring, f"{label}: springs[{index}]")
    variables = _mapping(record["variables"], f"{label}: variables")
    for name, value in variables.items():
        if not _is_number(value):
            raise InputError(f"{label}: variables.{name}: expected a finite number, got {_shown(value)}")
        if abs(value) > MAX_VALUE:
            raise InputError(f"{label}: variables.{name}: {value:g} is beyond ±{MAX_VALUE:g} (SI units)")


def _check_solver(value: Any, label: str) -> None:
    """The record's ``solver``: a mapping whose ``method`` and ``status`` are strings and ``seed`` an integer."""
    solver = _mapping(value, f"{label}: solver")
    for key in ("method", "status"):
        if key in solver and not isinstance(solver[key], str):
            raise InputError(f"{label}: solver.{key}: expected a string, got {_shown(solver[key])}")
    if solver.get("seed") is not None and (isinstance(solver["seed"], bool) or not isinstance(solver["seed"], int)):
        raise InputError(f"{label}: solver.seed: expected an integer, got {_shown(solver['seed'])}")


def _check_scenarios(scenarios: dict[str, Any] | None, label: str) -> None:
    """The record's ``scenarios`` (when there are any): a list of ``cases`` and of ``per_scenario`` names."""
    if not scenarios:
        return
    cases = scenarios.get("cases")
    if not isinstance(cases, list) or not all(isinstance(case, dict) for case in cases):
        raise InputError(f"{label}: scenarios.cases: expected a list of scenario records, got {_shown(cases)}")
    per_scenario = scenarios.get("per_scenario", [])
    if not isinstance(per_scenario, list) or not all(isinstance(name, str) for name in per_scenario):
        raise InputError(
            f"{label}: scenarios.per_scenario: expected a list of variable names, got {_shown(per_scenario)}"
        )


def check_design_mechanism(
    record: dict[str, Any], mechanism: Mechanism, label: str, own_workspace: bool = True
) -> None:
    """The record fits ``mechanism``: its joints (weights, sample width), and its springs' bodies and joints.

    ``own_workspace``: the saved samples are used (their width is checked too).
    """
    saved_joints = list(record["weights"])
    joints = mechanism.joint_names
    source = record.get("mechanism", {})
    made_for = source.get("robot") or source.get("path") or "another URDF"
    if saved_joints and saved_joints != joints:
        raise InputError(
            f"{label}: this design was made for a different mechanism (joints {', '.join(saved_joints)}); "
            f"mechanism {mechanism.name!r} ({made_for}) has joints {', '.join(joints)}"
        )
    width = len(record["workspace"]["joint_values"][0])
    if own_workspace and width != mechanism.nv:
        raise InputError(
            f"{label}: workspace.joint_values: rows of {width} values, but mechanism {mechanism.name!r} "
            f"has {mechanism.nv} joints ({', '.join(joints)}); this design was made for a different "
            "mechanism"
        )
    bodies = set(mechanism.body_names)
    for index, spring in enumerate(record["springs"]):
        ends = [(end, spring.get(end)) for end in ("a", "b")]
        if isinstance(spring.get("path"), list):  # a routed spring: its anchors in order
            ends += [(f"path[{i}]", anchor) for i, anchor in enumerate(spring["path"])]
        for end, anchor in ends:
            body = anchor.get("body") if isinstance(anchor, dict) else None
            if isinstance(body, str) and body not in bodies:
                raise InputError(
                    f"{label}: springs[{index}].{end}.body: this design was made for a different "
                    f"mechanism: body {body!r} is not in mechanism {mechanism.name!r} ({made_for}); "
                    f"bodies: {', '.join(mechanism.body_names)}"
                )
        joint = spring.get("joint")
        if isinstance(joint, str) and joint not in joints:
            raise InputError(
                f"{label}: springs[{index}].joint: this design was made for a different mechanism: "
                f"joint {joint!r} is not in mechanism {mechanism.name!r}; joints: {', '.join(joints)}"
            )


def _mapping(value: Any, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise InputError(f"{where}: expected a mapping, got {_shown(value)}")
    return value


def _is_number(value: Any) -> bool:
    """A finite int or float (not a bool), within the range of a float."""
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


def _shown(value: Any, limit: int = 80) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"
