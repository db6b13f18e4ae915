"""A validation error of the config records as one line: ``<file>: <key path>: <what>``.

:func:`validated` validates a mapping by a record and turns a :class:`pydantic.ValidationError`
into the one-line :class:`~springbalance.errors.ConfigError` of the rest of the config code, whose
key path names a spring by its name (``springs[0] 'shoulder'.b.box``).
"""

from __future__ import annotations

from typing import Any

import pydantic
from pydantic_core import ErrorDetails

from springbalance.errors import ConfigError
from springbalance.io.schema.fields import EXPECTED_TYPES, abbreviated

_BOUNDS = {
    "greater_than": ("gt", ">"),
    "greater_than_equal": ("ge", "≥"),
    "less_than": ("lt", "<"),
    "less_than_equal": ("le", "≤"),
}


def validated(
    model: type[pydantic.BaseModel] | pydantic.TypeAdapter,
    data: Any,
    where: str,
    top: bool = False,
    springs_at: tuple = ("springs",),
) -> Any:
    """``data`` validated by ``model`` (a pydantic model class or a :class:`pydantic.TypeAdapter`).

    Raises:
        ConfigError: ``<where>: <key path>: <what>`` for the first problem; ``top`` when ``where``
            is a file label (a colon before the key path) rather than a key path. ``springs_at`` is the
            key path of the spring list within ``data``: the key paths of spring errors name the spring.
    """
    validate = model.model_validate if isinstance(model, type) else model.validate_python
    try:
        return validate(data)
    except pydantic.ValidationError as error:
        raise ConfigError(describe(error, data, where, top, springs_at)) from None


def describe(
    error: pydantic.ValidationError, data: Any, where: str, top: bool = False, springs_at: tuple = ("springs",)
) -> str:
    """The one-line message of the most telling error of ``error`` (see :func:`validated`)."""
    found = [(detail, _steps(detail, data)) for detail in error.errors(include_url=False)]
    # a wrong type next to other errors of the same value is a branch of a union that was not meant
    meant = [
        (detail, steps)
        for detail, steps in found
        if not (
            detail["type"] in EXPECTED_TYPES
            and any(other is not detail and other_steps[: len(steps)] == steps for other, other_steps in found)
        )
    ]
    detail, steps = (meant or found)[0]
    if not meant and detail["type"] in EXPECTED_TYPES:  # only wrong types: list what each branch takes
        options = list(
            dict.fromkeys(
                EXPECTED_TYPES[other["type"]]
                for other, other_steps in found
                if other_steps == steps and other["type"] in EXPECTED_TYPES
            )
        )
        what = f"expected {' or '.join(options)}, got {abbreviated(detail['input'])}"
    elif detail["type"] == "missing":
        steps, what = steps[:-1], f"missing key {steps[-1][0]!r}"
    else:
        what = _what(detail)
    key = (detail.get("ctx") or {}).get("config_key")
    if key:
        steps = [*steps, (key, False)]
    path = _path(steps, data, springs_at)
    if top:
        prefix = f"{where}: {path}" if path else where
    else:
        prefix = where + ("" if not path or path.startswith("[") else ".") + path
    return f"{prefix}: {what}"


def _what(detail: ErrorDetails) -> str:
    kind, value, context = detail["type"], detail["input"], detail.get("ctx") or {}
    if "message" in context:
        return context["message"]
    if kind in EXPECTED_TYPES:
        return f"expected {EXPECTED_TYPES[kind]}, got {abbreviated(value)}"
    if kind in _BOUNDS:
        name, sign = _BOUNDS[kind]
        bound = context[name]
        bound = int(bound) if isinstance(bound, float) and bound.is_integer() else bound
        return f"must be {sign} {bound}, got {abbreviated(value)}"
    if kind == "finite_number":
        return f"{value!r} is not allowed; every number must be finite"
    if kind in ("too_short", "too_long"):
        length = context.get("min_length" if kind == "too_short" else "max_length")
        return f"expected {'at least' if kind == 'too_short' else 'at most'} {length} items, got {abbreviated(value)}"
    if kind == "literal_error":
        return f"unknown value {abbreviated(value)}; valid: {context.get('expected')}"
    if kind == "extra_forbidden":
        return "unknown key"
    message = detail["msg"]
    return f"{message[:1].lower()}{message[1:]}, got {abbreviated(value)}"


def _steps(detail: ErrorDetails, data: Any) -> list[tuple[object, bool]]:
    """The key path of an error in ``data``: ``(key, is_list_index)`` steps. Parts of pydantic's
    location that are not keys of the data (union tags) are left out."""
    loc = detail["loc"]
    steps: list[tuple[object, bool]] = []
    node = data
    for position, part in enumerate(loc):
        if isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node):
            steps.append((part, True))
            node = node[part]
        elif isinstance(node, dict) and part in node:
            steps.append((part, False))
            node = node[part]
        elif detail["type"] == "missing" and position == len(loc) - 1:
            steps.append((part, False))
    return steps


def _path(steps: list[tuple[object, bool]], data: Any, springs_at: tuple) -> str:
    """``springs[0] 'shoulder'.b.box``: keys joined by dots, list indices in brackets; a spring's
    name follows its index (unless the error is about its type or name)."""
    text = ""
    node: Any = data  # the config's own data: any JSON value
    for position, (part, index) in enumerate(steps):
        text += f"[{part}]" if index else (f".{part}" if text else str(part))
        inside = isinstance(node, (dict, list)) and (index or part in node)  # a list's steps are int indices
        node = node[part] if inside else None
        spring = index and position == len(springs_at) and tuple(key for key, _ in steps[:position]) == springs_at
        following = steps[position + 1][0] if position + 1 < len(steps) else None
        if spring and isinstance(node, dict) and following not in ("type", "name"):
            name = node.get("name")
            if isinstance(name, str) and name:
                text += f" {name!r}"
    return text
