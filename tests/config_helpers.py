"""Shared by the config and CLI tests: edit a nested config record by key path."""

import copy


def edited_record(base: dict, **changes) -> dict:
    """A deep copy of ``base`` with ``section__key=value`` changes (value None deletes the key);
    list entries are addressed by index, e.g. ``springs__0__stiffness``."""
    record = copy.deepcopy(base)
    for dotted, value in changes.items():
        keys = dotted.split("__")
        node = record
        for key in keys[:-1]:
            node = node[int(key)] if isinstance(node, list) else node[key]
        if value is None:
            del node[keys[-1]]
        else:
            node[keys[-1]] = value
    return record
