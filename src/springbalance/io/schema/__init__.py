"""The config file's schema: pydantic records of every section, its JSON Schema, and one-line errors.

Each section of a config file is a :class:`Record` (a pydantic model that rejects unknown keys,
takes types strictly and numbers only when finite), named ``<Name>Record``. The modules:

- :mod:`~springbalance.io.schema.fields`: the :class:`Record` base, the field helpers and value types;
- :mod:`~springbalance.io.schema.records`: the records of the sections (anchors, parameters,
  mechanism, workspace, solve, scenarios, clearance);
- :mod:`~springbalance.io.schema.spring_records`: the spring records, built from the law registry
  :data:`springbalance.springs.SPRING_TYPES` (a new law module appears here without an edit);
- :mod:`~springbalance.io.schema.config_file`: the record of a whole file (:func:`config_model`);
- :mod:`~springbalance.io.schema.validation`: :func:`validated` turns a :class:`pydantic.ValidationError`
  into the one-line :class:`~springbalance.errors.ConfigError` ``<file>: <key path>: <what>``;
- :mod:`~springbalance.io.schema.json_schema`: the JSON Schema (:func:`json_schema`, :func:`schema_text`).

The records check shape and types only. What needs the URDF (bodies and joints that exist),
orders between values (lower ≤ upper) and the rules between keys (one of ``urdf``/``robot``,
keys that apply to a workspace kind) are checked by :mod:`springbalance.io.config` after them.

Units are SI (m, N, N/m, rad, kg, m/s²) unless ``workspace.degrees`` is true (then angles of
revolute joints in the workspace section are in degrees).

The records' old names (``Anchor``, ``Free``, ``Workspace``, ...) stay importable from this module
for one release, with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

from springbalance.deprecation import moved_names
from springbalance.io.schema import records
from springbalance.io.schema.config_file import TITLE, config_model
from springbalance.io.schema.fields import (
    DEFAULT_SPRING_TYPE,
    KIND_KEYS,
    REQUIRED_SECTIONS,
    SECTIONS,
    WORKSPACE_KINDS,
    Aggregate,
    Counting,
    Direction,
    Interval,
    Method,
    NonNegative,
    Number,
    Objective,
    Positive,
    Record,
    Seed,
    Text,
    Vector2,
    Vector3,
    WorkspaceKind,
)
from springbalance.io.schema.json_schema import JSON_SCHEMA_DIALECT, json_schema, schema_text
from springbalance.io.schema.records import (
    RECORDS,
    SCHEMA_NAMES,
    AnchorRecord,
    BoxRecord,
    ClearanceRecord,
    CouplingRecord,
    FreeRecord,
    LoadCaseRecord,
    MechanismRecord,
    MountPlaneRecord,
    NonNegativeFreeRecord,
    NonNegativeParameter,
    Parameter,
    PathPointRecord,
    PayloadRangeRecord,
    PayloadRecord,
    PlaneRecord,
    PulleySizeRecord,
    RoutedSpringRecord,
    ScenariosRecord,
    SegmentRecord,
    SolveRecord,
    Weights,
    WorkspaceFileRecord,
    WorkspaceRecord,
)
from springbalance.io.schema.spring_records import spring_list, spring_list_adapter, spring_model
from springbalance.io.schema.validation import describe, validated

__all__ = [
    "DEFAULT_SPRING_TYPE",
    "JSON_SCHEMA_DIALECT",
    "KIND_KEYS",
    "RECORDS",
    "REQUIRED_SECTIONS",
    "SCHEMA_NAMES",
    "SECTIONS",
    "TITLE",
    "WORKSPACE_KINDS",
    "Aggregate",
    "Counting",
    "Direction",
    "Interval",
    "Method",
    "NonNegative",
    "NonNegativeParameter",
    "Number",
    "Objective",
    "Parameter",
    "Positive",
    "Seed",
    "Text",
    "Vector2",
    "Vector3",
    "Weights",
    "WorkspaceKind",
    "Record",
    "AnchorRecord",
    "BoxRecord",
    "ClearanceRecord",
    "CouplingRecord",
    "FreeRecord",
    "LoadCaseRecord",
    "MechanismRecord",
    "MountPlaneRecord",
    "NonNegativeFreeRecord",
    "PathPointRecord",
    "PayloadRangeRecord",
    "PayloadRecord",
    "PlaneRecord",
    "PulleySizeRecord",
    "RoutedSpringRecord",
    "ScenariosRecord",
    "SegmentRecord",
    "SolveRecord",
    "WorkspaceFileRecord",
    "WorkspaceRecord",
    "config_model",
    "describe",
    "json_schema",
    "schema_text",
    "spring_list",
    "spring_list_adapter",
    "spring_model",
    "validated",
]


__getattr__ = moved_names(__name__, {name: (records, record.__name__) for name, record in RECORDS.items()})
