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


#: the law of a record without ``type``
DEFAULT_TYPE = "extension"


def spring_types() -> list[str]:
    """The ``type`` names of the registered laws (each once, whether or not it has an ideal variant)."""
    return list(dict.fromkeys(cls.kind for cls in SPRING_TYPES.values()))


def law_of(record: dict, where: str = "spring") -> type[Spring]:
    """The law class of a record: its ``type`` (default ``extension``), and for the laws made as real
    coils, ``ideal: true`` for the idealised law instead of the coil."""
    kind = record.get("type", DEFAULT_TYPE)
    if not isinstance(kind, str) or kind not in spring_types():
        raise InputError(f"{where}.type: unknown spring type {kind!r}; valid: {', '.join(spring_types())}")
    ideal = record.get("ideal", False)
    if not isinstance(ideal, bool):
        raise InputError(f"{where}.ideal: expected true or false, got {ideal!r}")
    if ideal and f"{kind}:ideal" not in SPRING_TYPES:
        raise InputError(f"{where}.ideal: a {kind!r} spring has no ideal variant (only "
                         f"{', '.join(cls.kind for cls in SPRING_TYPES.values() if cls.ideal)} do)")
    cls = SPRING_TYPES[f"{kind}:ideal" if ideal else kind]
    hint = ideal_law_hint(cls, record)
    if hint:
        raise InputError(f"{where}: {hint}")
    return cls


def ideal_law_hint(cls: type[Spring], record: dict) -> str | None:
    """For a coil record that uses a key of the ideal law (``stiffness``, ``free_length``, ...), the
    message that says to write ``ideal: true`` or to give the coil; None otherwise."""
    ideal = SPRING_TYPES.get(f"{cls.kind}:ideal")
    if cls.ideal is not False or ideal is None:
        return None
    own = {"name", "type", *cls.ends, *cls.parameter_units, *cls.option_keys}
    foreign = [key for key in record if key not in own and (key in ideal.parameter_units or key in ideal.option_keys)]
    if not foreign:
        return None
    return (f"unknown key {foreign[0]!r} for a helical {cls.kind} coil, which is designed by "
            f"{', '.join(cls.parameter_units)}: write ideal: true for the mathematical {cls.kind} law "
            f"({', '.join(ideal.parameter_units)})")


def spring_from_dict(record, where: str = "spring") -> Spring:
    """Build a spring from its record (as in configs and saved designs).

    Two-point springs: ``{name?, type, a: anchor, b: anchor, <parameters>, <options>}``;
    torsional springs: ``{name?, type: torsional, joint, <parameters>, <options>}``. Each
    parameter is a number or ``{lower, upper, init?}``; the options of each type are its
    class's ``option_keys``.
    """
    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping, got {record!r}")
    cls = law_of(record, where)
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

