"""The objects of a config's sections, built from their validated records.

Here are the checks the records cannot make: bodies and joints that exist in the mechanism,
lower ≤ upper, exactly one of ``urdf``/``robot`` (and of ``cases``/``payload_range``), the keys
that apply to a workspace kind. Joint ranges and couplings are in rad or m, or degrees for
revolute joints with ``workspace.degrees``; masses [kg]; points [m] in the body frame.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from springbalance.design.scenarios import Payload, Scenario, payload_scenarios
from springbalance.errors import ConfigError
from springbalance.io.config_errors import prefixed
from springbalance.io.samples import read_samples_file, value_rows
from springbalance.io.schema import (
    KIND_KEYS,
    CouplingRecord,
    MechanismRecord,
    ScenariosRecord,
    SolveRecord,
    WorkspaceRecord,
)
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Coupling, Workspace
from springbalance.springs.laws import Spring
from springbalance.springs.records import spring_from_dict


def mechanism_from_record(model: MechanismRecord, base_dir: str | Path, where: str) -> Mechanism:
    """The :class:`Mechanism` of a validated ``mechanism`` record (gravity [m/s²]); a relative ``urdf`` is
    relative to ``base_dir``."""
    sources = [key for key in ("urdf", "robot") if getattr(model, key) is not None]
    if len(sources) != 1:
        given = f" (got {' and '.join(sources)})" if sources else ""
        raise ConfigError(
            f"{where}: give exactly one of 'urdf' (a file) or 'robot' (an example-robot-data name){given}"
        )
    options: dict[str, Any] = {
        "gravity": model.gravity,
        "mimic": model.mimic,
        "validate": model.validate,
        "floor": model.floor,
    }
    if model.pseudo_bases:
        options["pseudo_bases"] = [base if isinstance(base, str) else base.model_dump() for base in model.pseudo_bases]
    if model.urdf is not None:
        urdf_path = Path(base_dir) / Path(model.urdf).expanduser()
        with prefixed(f"{where}.urdf"):
            return Mechanism.from_urdf(urdf_path, **options)
    with prefixed(f"{where}.robot"):
        return Mechanism.from_robot(model.robot, **options)


def workspace_from_record(
    mechanism: Mechanism, model: WorkspaceRecord | None, base_dir: str | Path, where: str
) -> Workspace:
    """The :class:`Workspace` of a validated ``workspace`` record (None: 1024 Sobol points of the URDF limits)."""
    model = WorkspaceRecord() if model is None else model
    kind = model.kind
    for key in tuple(WorkspaceRecord.model_fields):
        if key in model.model_fields_set and key not in ("kind", "degrees") and key not in KIND_KEYS[kind]:
            users = [k for k, keys in KIND_KEYS.items() if key in keys]
            raise ConfigError(
                f"{where}: key {key!r} does not apply to kind {kind!r} (only to {', '.join(users)}); "
                f"keys of {kind}: kind, degrees, {', '.join(KIND_KEYS[kind])}"
            )
    degrees = model.degrees
    ranges = _ranges(mechanism, model.ranges, f"{where}.ranges")
    couplings = _couplings(mechanism, model.couplings, degrees, f"{where}.couplings")
    n = model.n
    if isinstance(n, dict) and kind != "grid":
        raise ConfigError(f"{where}.n: expected an integer (a mapping joint → count is for kind grid), got {n!r}")

    with prefixed(where):
        if kind == "grid":
            if isinstance(n, dict):
                n = dict(_joint_mapping(mechanism, n, f"{where}.n"))
            return Workspace.grid(
                mechanism, n=16 if n is None else n, ranges=ranges, couplings=couplings, degrees=degrees
            )
        assert not isinstance(n, dict)  # a mapping is rejected above for every kind but grid
        if kind in ("sobol", "random"):
            constructor = Workspace.sobol if kind == "sobol" else Workspace.random
            return constructor(
                mechanism,
                n=1024 if n is None else n,
                ranges=ranges,
                couplings=couplings,
                degrees=degrees,
                seed=model.seed,
            )
        if kind == "sweep":
            if model.joint is None:
                raise ConfigError(
                    f"{where}: kind 'sweep' needs key 'joint' (one of {', '.join(mechanism.joint_names)})"
                )
            joint = _known_joint(mechanism, model.joint, f"{where}.joint")
            n = 181 if n is None else n
            if n < 2:
                raise ConfigError(f"{where}.n: must be ≥ 2, got {n}")
            return Workspace.sweep(mechanism, joint, n=n, ranges=ranges, degrees=degrees)
        # array
        if (model.values is None) == (model.file is None):
            raise ConfigError(f"{where}: kind 'array' needs exactly one of 'values' (rows of joint values) or 'file'")
        if model.values is not None:
            values = value_rows(mechanism, model.values, f"{where}.values")
        else:
            values = read_samples_file(mechanism, Path(base_dir) / Path(model.file).expanduser(), f"{where}.file")
        with prefixed(f"{where}.{'values' if model.values is not None else 'file'}"):
            return Workspace.from_array(mechanism, values, ordered=model.ordered, degrees=degrees)


def springs_from_records(mechanism: Mechanism, records: list, where: str) -> list[Spring]:
    """Springs of validated ``records`` (:func:`springbalance.springs.spring_from_dict`), bodies and joints checked."""
    springs = []
    for index, record in enumerate(records):
        label = f"{where}[{index}]"
        spring = spring_from_dict(record, label)
        name = f" {spring.name!r}" if spring.name else ""
        for end, anchor in spring.anchors.items():
            body = anchor.body
            if body not in mechanism.body_names:
                raise ConfigError(
                    f"{label}{name}.{end}.body: unknown body {body!r} in mechanism {mechanism.name!r}; "
                    f"bodies: {', '.join(mechanism.body_names)}"
                )
        for joint in spring.joints:
            if joint not in mechanism.joint_names:
                raise ConfigError(
                    f"{label}{name}.joint: unknown joint {joint!r} in mechanism {mechanism.name!r}; "
                    f"joints: {', '.join(mechanism.joint_names)}"
                )
        springs.append(spring)
    return springs


def solve_options_from_record(model: SolveRecord | None) -> dict[str, Any]:
    """The keys given in the ``solve`` section (the others take the solver's defaults)."""
    if model is None:
        return {}
    return {key: getattr(model, key) for key in tuple(SolveRecord.model_fields) if key in model.model_fields_set}


def scenarios_from_record(mechanism: Mechanism, model: ScenariosRecord | None, where: str) -> dict[str, Any]:
    """Keyword arguments ``scenarios``, ``per_scenario``, ``aggregate`` of :class:`DesignProblem` (none without
    a ``scenarios`` section); payload masses [kg], points [m] in the body frame."""
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
                point = (0.0, 0.0, 0.0) if payload.point is None else tuple(payload.point)
                with prefixed(spot):
                    items.append(Payload(body, payload.mass, point))
            scale = case.mass_scale
            if isinstance(scale, dict):
                scale = {_known_body(mechanism, body, f"{label}.mass_scale"): value for body, value in scale.items()}
            with prefixed(label):
                scenarios.append(Scenario(name, items, scale))
    else:
        spec = model.payload_range
        label = f"{where}.payload_range"
        body = _known_body(mechanism, spec.body, f"{label}.body")
        point = [0.0, 0.0, 0.0] if spec.point is None else spec.point
        scenarios = payload_scenarios(body, spec.masses, point)
    return {"scenarios": scenarios, "per_scenario": model.per_scenario, "aggregate": model.aggregate}


def _known_body(mechanism: Mechanism, name: Any, where: str) -> str:
    if not isinstance(name, str) or name not in mechanism.body_names:
        raise ConfigError(
            f"{where}: unknown body {name!r} in mechanism {mechanism.name!r}; bodies: {', '.join(mechanism.body_names)}"
        )
    return name


def weights_from_record(mechanism: Mechanism, record: dict | None, where: str) -> dict[str, float] | None:
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


def _couplings(mechanism: Mechanism, records: list[CouplingRecord] | None, degrees: bool, where: str) -> list[Coupling]:
    if records is None:
        return []
    couplings = []
    for index, record in enumerate(records):
        label = f"{where}[{index}]"
        lower, upper = record.range
        if lower > upper:
            raise ConfigError(f"{label}.range: lower {lower:g} > upper {upper:g}")
        with prefixed(f"{label}.expression"):
            coupling = Coupling.parse(record.expression, lower, upper, degrees=degrees)
        for joint in coupling.coefficients:
            if joint not in mechanism.joint_names:
                raise ConfigError(
                    f"{label}.expression: unknown joint {joint!r} in {record.expression!r}; "
                    f"joints: {', '.join(mechanism.joint_names)}"
                )
        couplings.append(coupling)
    return couplings


def _joint_mapping(mechanism: Mechanism, record: Any, where: str) -> dict:
    if not isinstance(record, dict):
        raise ConfigError(f"{where}: expected a mapping joint name → value, got {record!r}")
    mapping = {}
    for joint, value in record.items():
        mapping[_known_joint(mechanism, joint, where)] = value
    return mapping


def _known_joint(mechanism: Mechanism, name: Any, where: str) -> str:
    name = str(name)
    if name not in mechanism.joint_names:
        raise ConfigError(
            f"{where}: unknown joint {name!r} in mechanism {mechanism.name!r}; "
            f"joints: {', '.join(mechanism.joint_names)}"
        )
    return name
