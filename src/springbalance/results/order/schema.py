"""The JSON schema (draft 2020-12) of ``order.json`` (:func:`springbalance.results.order.page.order_record`).

Numbers are SI (m, N, N/m); a field's ``value`` is a number, a text or null (then its ``note`` says why),
its ``tolerance`` a number or null (then ``tolerance_note`` says why, or no tolerance applies).
"""

from __future__ import annotations

from typing import Any

_NUMBER_OR_NULL = {"type": ["number", "null"]}
_FIELD = {
    "type": "object",
    "required": ["key", "label", "value", "unit", "tolerance", "reference", "note", "tolerance_note"],
    "additionalProperties": False,
    "properties": {
        "key": {"type": "string", "pattern": "^[a-z0-9_]+$"},
        "label": {"type": "string", "minLength": 1},
        "value": {"type": ["number", "string", "null"]},
        "unit": {"enum": ["", "m", "N", "N/m", "1"]},
        "tolerance": {"type": ["number", "null"], "minimum": 0},
        "reference": {"type": "boolean"},
        "note": {"type": "string"},
        "tolerance_note": {"type": "string"},
    },
}
_STATE = {
    "type": "object",
    "required": ["state", "length", "load"],
    "properties": {"state": {"enum": ["free", "1", "2"]}, "length": {"type": "number"}, "load": {"type": "number"}},
}
_SPRING = {
    "type": "object",
    "required": ["name", "kind", "form", "fields", "tolerances", "duty", "geometry", "drawing", "states"],
    "properties": {
        "name": {"type": "string"},
        "kind": {"enum": ["extension", "compression"]},
        "form": {"enum": ["DIN 2099-1 (form A)", "DIN 2099-2 (form B)"]},
        "fields": {"type": "array", "items": _FIELD, "minItems": 20},
        "tolerances": {
            "type": "object",
            "required": ["grade", "standard", "free_length", "coil_diameter", "loads"],
            "properties": {
                "grade": {"enum": [1, 2, 3]},
                "standard": {"enum": ["DIN 2097", "EN 15800"]},
                "free_length": _NUMBER_OR_NULL,
                "coil_diameter": _NUMBER_OR_NULL,
                "loads": {"type": "array", "items": _NUMBER_OR_NULL, "minItems": 2, "maxItems": 2},
            },
        },
        "duty": {"type": "object", "required": ["cycles", "peened", "assumed", "margins"]},
        "geometry": {"type": "object", "additionalProperties": {"type": "number"}},
        "drawing": {"type": "string", "pattern": "^[A-Za-z0-9_.-]+\\.svg$"},
        "states": {"type": "array", "items": _STATE, "minItems": 3, "maxItems": 3},
    },
}
_BOM_ROW = {
    "type": "object",
    "required": ["item", "category", "description", "quantity", "body", "x_mm", "y_mm", "z_mm", "springs", "notes"],
    "properties": {
        "item": {"type": "integer", "minimum": 1},
        "category": {"enum": ["spring", "anchor", "pulley", "guide", "cable"]},
        "quantity": {"type": "integer", "minimum": 0},
        "x_mm": {"type": ["number", "string"]},
        "y_mm": {"type": ["number", "string"]},
        "z_mm": {"type": ["number", "string"]},
    },
}
#: the schema of order.json
ORDER_SCHEMA: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "springbalance spring order",
    "type": "object",
    "required": ["format", "design", "springbalance", "date", "options", "springs", "not_quotable", "bom"],
    "properties": {
        "format": {"const": "springbalance-order/1"},
        "design": {"type": "string"},
        "springbalance": {"type": "string"},
        "date": {"type": "string", "format": "date"},
        "options": {
            "type": "object",
            "required": ["grade", "finish", "direction", "quantity"],
            "properties": {
                "grade": {"enum": [1, 2, 3]},
                "finish": {"type": ["string", "null"]},
                "direction": {"enum": ["right-hand", "left-hand"]},
                "quantity": {"type": "integer", "minimum": 1},
            },
        },
        "springs": {"type": "array", "items": _SPRING, "minItems": 1},
        "not_quotable": {
            "type": "array",
            "items": {"type": "object", "required": ["name", "type", "reason"]},
        },
        "bom": {"type": "array", "items": _BOM_ROW, "minItems": 1},
        "partial": {"type": "string"},
    },
}
