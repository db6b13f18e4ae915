"""The JSON Schema (draft 2020-12) of a config file, generated from its records.

The records are named ``<Name>Record`` in Python; the schema keeps their published names
(:data:`springbalance.io.schema.records.SCHEMA_NAMES`), so that docs/config.schema.json does not
change with the Python names.
"""

from __future__ import annotations

import json
from typing import Any

from pydantic.json_schema import GenerateJsonSchema

from springbalance.io.schema.config_file import config_model
from springbalance.io.schema.records import SCHEMA_NAMES

JSON_SCHEMA_DIALECT = "https://json-schema.org/draft/2020-12/schema"


class _SchemaGenerator(GenerateJsonSchema):
    """Pydantic's JSON Schema without a title on every property (the descriptions say it all), and with
    the published names of the records as the keys of their definitions."""

    def field_title_should_be_set(self, schema: Any) -> bool:
        return False

    def normalize_name(self, name: str) -> str:
        return super().normalize_name(SCHEMA_NAMES.get(name, name))


def json_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a config file, for editors and other validators."""
    schema = config_model().model_json_schema(schema_generator=_SchemaGenerator)
    first = ("title", "description", "type", "properties", "required", "additionalProperties")
    ordered = {key: schema[key] for key in first if key in schema}
    rest = {key: value for key, value in schema.items() if key not in ordered and key != "$defs"}
    return {"$schema": JSON_SCHEMA_DIALECT, **ordered, **rest, "$defs": schema.get("$defs", {})}


def schema_text() -> str:
    """:func:`json_schema` as indented JSON text (what ``springbalance schema`` prints)."""
    return json.dumps(json_schema(), indent=2, ensure_ascii=False) + "\n"
