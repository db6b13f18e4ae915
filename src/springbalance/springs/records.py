"""Spring records: the mapping that configs and saved designs hold for one spring, and back.

A record is ``{name?, type, <ends>, <parameters>, <options>}``: the law (``type``) is looked up
in :data:`~springbalance.springs.laws.base.SPRING_TYPES`, and its class says which ends
(``a``/``b`` anchors or a ``joint``), parameters and options it takes.
"""

from __future__ import annotations

from springbalance.errors import InputError
from springbalance.springs.laws.base import SPRING_TYPES, Spring
from springbalance.springs.mass import mass_from_record
from springbalance.springs.params import anchor_from_dict, check_keys, value_from_record
from springbalance.springs.sizing import helical_from_dict


def spring_from_dict(record, where: str = "spring") -> Spring:
    """Build a spring from its record (as in configs and saved designs).

    Two-point springs: ``{name?, type, a: anchor, b: anchor, <parameters>, <options>}``;
    torsional springs: ``{name?, type: torsional, joint, <parameters>, <options>}``. Each
    parameter is a number or ``{lower, upper, init?}``; the options of each type are its
    class's ``option_keys``.
    """
    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping, got {record!r}")
    kind = record.get("type", "extension")
    if not isinstance(kind, str) or kind not in SPRING_TYPES:
        raise InputError(f"{where}.type: unknown spring type {kind!r}; valid: {', '.join(SPRING_TYPES)}")
    cls = SPRING_TYPES[kind]
    ends = cls.ends
    check_keys(record, ("name", "type", *ends, *cls.parameter_units, *cls.option_keys), where)
    name = record.get("name")
    where = f"{where} {name!r}" if name else where
    for end in ends:
        if end not in record:
            raise InputError(f"{where}: missing key {end!r} (" +
                             ("the joint it acts on)" if end == "joint" else "the anchor of that end)"))
    parameters = {key: value_from_record(record[key], f"{where}.{key}") for key in cls.parameter_units if key in record}
    extra = {key: record[key] for key in cls.option_keys if key in record}
    for key in extra:
        if cls.option_types[key] is bool and not isinstance(extra[key], bool):
            raise InputError(f"{where}.{key}: expected true or false, got {extra[key]!r}")
    if "mass" in extra:
        extra["mass"] = mass_from_record(extra["mass"], f"{where}.mass")
    if "helical" in extra:
        extra["helical"] = helical_from_dict(extra["helical"], f"{where}.helical")
    name = None if name is None else str(name)
    try:
        if ends == ("joint",):
            if not isinstance(record["joint"], str):
                raise InputError(f"joint: expected a joint name, got {record['joint']!r}")
            return cls(record["joint"], name, **parameters, **extra)
        a = anchor_from_dict(record["a"], f"{where}.a")
        b = anchor_from_dict(record["b"], f"{where}.b")
        return cls(a, b, name, **parameters, **extra)
    except InputError as error:
        if str(error).startswith(where):
            raise
        raise InputError(f"{where}: {error}") from None

