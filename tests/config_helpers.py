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


#: One extension spring from just above the shoulder of urdf/two_link_planar.urdf to link1: with
#: the elbow held straight the shoulder carries a single-link load that this spring balances well.
SHOULDER_SPRING = {
    "name": "s1",
    "type": "extension",
    "ideal": True,
    "a": {"body": "universe", "point": [0, 0, 0.1]},
    "b": {"body": "link1", "box": {"lower": [0.05, 0, 0], "upper": [0.5, 0, 0]}},
    "stiffness": {"lower": 0, "upper": 10000},
    "free_length": {"lower": 0.05, "upper": 1.0},
}
