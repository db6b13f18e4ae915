"""Spring records: the mapping that configs and saved designs hold for one spring, and back.

A record is ``{name?, type, <ends>, <parameters>, <options>}``: the law (``type``) is looked up
in :data:`~springbalance.springs.laws.base.SPRING_TYPES`, and its class says which ends
(``a``/``b`` anchors or a ``joint``), parameters and options it takes.
"""

from __future__ import annotations

from typing import Any, Callable, cast

from springbalance.errors import InputError
from springbalance.springs.helical_option import helical_from_dict
from springbalance.springs.laws.spring import SPRING_TYPES, Spring
from springbalance.springs.mass import mass_from_record
from springbalance.springs.params import Pulley, anchor_from_dict, check_keys, path_from_dict, value_from_record

#: the law of a record without ``type``
DEFAULT_TYPE = "extension"


#: the ``type`` of a routed spring's record (its law is the record's ``spring``)
ROUTED = "routed"


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
        raise InputError(
            f"{where}.ideal: a {kind!r} spring has no ideal variant (only "
            f"{', '.join(cls.kind for cls in SPRING_TYPES.values() if cls.ideal)} do)"
        )
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
    return (
        f"unknown key {foreign[0]!r} for a helical {cls.kind} coil, which is designed by "
        f"{', '.join(cls.parameter_units)}: write ideal: true for the mathematical {cls.kind} law "
        f"({', '.join(ideal.parameter_units)})"
    )


def spring_from_dict(record: dict[str, Any], where: str = "spring", **routing: Any) -> Spring:
    """Build a spring from its record (as in configs and saved designs).

    Two-point springs: ``{name?, type, a: anchor, b: anchor, <parameters>, <options>}``;
    torsional springs: ``{name?, type: torsional, joint, <parameters>, <options>}``. Each
    parameter is a number or ``{lower, upper, init?}``; the options of each type are its
    class's ``option_keys``. Routed springs: ``{name?, type: routed, path, spring, cable_length}``
    (``routing``, the ``via`` and ``cable_length`` of a routed spring's law, is how that is built).
    """
    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping, got {record!r}")
    if record.get("type") == ROUTED:
        return _routed_from_dict(record, where)
    cls = law_of(record, where)
    ends = cls.ends
    check_keys(record, ("name", "type", *ends, *cls.parameter_units, *cls.option_keys), where)
    name = record.get("name")
    where = f"{where} {name!r}" if name else where
    for end in ends:
        if end not in record:
            raise InputError(
                f"{where}: missing key {end!r} ("
                + ("the joint it acts on)" if end == "joint" else "the anchor of that end)")
            )
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
    make = cast(Callable[..., Spring], cls)  # each law's constructor takes its own ends and options
    try:
        if ends == ("joint",):
            if not isinstance(record["joint"], str):
                raise InputError(f"joint: expected a joint name, got {record['joint']!r}")
            return make(record["joint"], name, **parameters, **extra)
        anchors = [anchor_from_dict(record[end], f"{where}.{end}") for end in ends]  # a, b (or a directed force's a)
        return make(*anchors, name, **parameters, **extra, **routing)
    except InputError as error:
        if str(error).startswith(where):
            raise
        raise InputError(f"{where}: {error}") from None


def _routed_from_dict(record: dict, where: str) -> Spring:
    """``{name?, type: routed, path: [point, pulley…, point], spring: {law record without ends}, cable_length}``.

    The law is any two-point law (``spring.type``, default ``extension``); the path's first point
    is the spring's fixed end, the last the cable's end, and the points between are pulleys
    (``pulley: {radius}``) or guide points.
    """
    check_keys(record, ("name", "type", "path", "spring", "cable_length"), where)
    name = record.get("name")
    where = f"{where} {name!r}" if name else where
    for key in ("path", "spring", "cable_length"):
        if key not in record:
            raise InputError(f"{where}: missing key {key!r} of a routed spring")
    law = record["spring"]
    if not isinstance(law, dict):
        raise InputError(
            f"{where}.spring: expected the spring's law as a mapping {{type?, stiffness, ...}}, got {law!r}"
        )
    if law.get("type") == ROUTED:
        raise InputError(f"{where}.spring.type: the law of a routed spring is a two-point law, not 'routed'")
    if "cable_length" in law or "name" in law or any(end in law for end in ("a", "b", "joint", "path")):
        key = next(key for key in ("cable_length", "name", "a", "b", "joint", "path") if key in law)
        raise InputError(f"{where}.spring.{key}: give it on the routed spring itself, not in its law")
    law = _coil_options(law, f"{where}.spring")
    cls = law_of(law, f"{where}.spring")
    if cls.ends != ("a", "b"):
        raise InputError(f"{where}.spring.type: a routed spring needs a two-point law, not {cls.kind!r}")
    path = path_from_dict(record["path"], f"{where}.path")
    cable = value_from_record(record["cable_length"], f"{where}.cable_length")
    inner = {**law, "a": path[0][0].to_dict(), "b": path[-1][0].to_dict()}
    if name is not None:
        inner["name"] = name
    return spring_from_dict(
        inner, f"{where}.spring", via=[Pulley(anchor, radius) for anchor, radius in path[1:-1]], cable_length=cable
    )


def _coil_options(law: dict, where: str) -> dict:
    """A coil law (``type`` extension or compression, not ``ideal: true``) takes ``helical: {material, ...}``
    as its own options (material, max_outer_diameter, ...); the ideal laws keep ``helical`` as theirs."""
    helical = law.get("helical")
    if helical is None or law.get("ideal", False) is True:
        return law
    kind = law.get("type", DEFAULT_TYPE)
    coil = SPRING_TYPES.get(kind) if isinstance(kind, str) else None
    if coil is None or coil.ideal is not False:
        return law
    check_keys(helical, [key for key in coil.option_keys if key not in ("ideal", "part_number")], f"{where}.helical")
    return {**{key: value for key, value in law.items() if key != "helical"}, **helical}
