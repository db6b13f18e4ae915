"""The names that moved in issue 26 still import from their old places for one release, with a DeprecationWarning:
the config records (``springbalance.io.schema.Anchor`` → ``AnchorRecord``) and the exports
(``springbalance.io.urdf`` / ``io.mjcf`` / ``io.export`` → ``springbalance.export``)."""

from __future__ import annotations

import importlib
import warnings

import pytest

from springbalance.export import common, mjcf, urdf
from springbalance.io import schema

OLD_RECORDS = [
    "Free",
    "NonNegativeFree",
    "Box",
    "Segment",
    "Plane",
    "MountPlane",
    "Anchor",
    "PulleySize",
    "PathPoint",
    "RoutedSpring",
    "Clearance",
    "Mechanism",
    "Coupling",
    "Workspace",
    "Solve",
    "Payload",
    "LoadCase",
    "PayloadRange",
    "Scenarios",
    "WorkspaceFile",
]


@pytest.mark.parametrize("name", OLD_RECORDS)
def test_old_record_name_warns_and_is_the_record(name):
    with pytest.warns(DeprecationWarning, match=f"io.schema.{name} is deprecated; use .*{name}Record"):
        record = getattr(schema, name)
    assert record is getattr(schema, f"{name}Record")
    assert record.model_config["title"] == name  # the JSON Schema keeps the old name


def test_old_record_names_are_all_covered():
    assert sorted(OLD_RECORDS) == sorted(schema.RECORDS)


def test_from_import_of_an_old_record_name_warns():
    with pytest.warns(DeprecationWarning):
        from springbalance.io.schema import Anchor  # noqa: F401


MOVED = (
    [
        ("springbalance.io.urdf", urdf, name)
        for name in ("SIDECAR_FORMAT", "URDF_NAMESPACE", "export_urdf", "sidecar_path", "urdf_strings")
    ]
    + [("springbalance.io.mjcf", mjcf, name) for name in ("MUJOCO_MESH_FORMATS", "export_mjcf", "mjcf_string")]
    + [
        ("springbalance.io.export", common, name)
        for name in ("ExportReport", "GROUND", "anchor_link_name", "law_warnings")
    ]
)


@pytest.mark.parametrize(("old", "new", "name"), MOVED)
def test_moved_export_name_warns_and_is_the_new_one(old, new, name):
    module = importlib.import_module(old)
    with pytest.warns(DeprecationWarning, match=f"{old}.{name} is deprecated; use {new.__name__}.{name}"):
        value = getattr(module, name)
    assert value is getattr(new, name)


def test_springs_from_urdf_keeps_its_place_without_a_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        from springbalance.io.urdf import springs_from_urdf  # noqa: F401


@pytest.mark.parametrize(
    "module", ["springbalance.io.schema", "springbalance.io.urdf", "springbalance.io.mjcf", "springbalance.io.export"]
)
def test_unknown_names_are_attribute_errors(module):
    with pytest.raises(AttributeError):
        _ = importlib.import_module(module).no_such_name
