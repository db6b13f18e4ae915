"""Shared by the config and CLI tests: edit a nested config record by key path; small configs."""

import copy
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]


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


def config_file(folder: Path, record: dict, name: str = "config.yaml") -> Path:
    """``record`` written as the YAML config ``folder/name``."""
    path = folder / name
    path.write_text(yaml.safe_dump(record, sort_keys=False))
    return path


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


#: A design that fails a check (``overlap``), quick to solve: urdf/two_link_planar_collision.urdf (link1's
#: collision box 0.5 × 0.04 × 0.04 m along x from its joint) with one zero-free-length spring from
#: (0.25, 0, −0.1) on the ground to (0.2, 0, 0.1) on link2. Near the pose (0, 0) link2's point is at
#: (0.7, 0, 0.1), and the spring's line crosses z = 0 at x = 0.25 + 0.45 · 0.1/0.2 = 0.475 m, inside link1's
#: box: whatever its stiffness, it overlaps link1 at every pose of the ±10° workspace. Only its stiffness is
#: free.
THROUGH = {
    "mechanism": {"urdf": str(ROOT / "urdf" / "two_link_planar_collision.urdf")},
    "workspace": {
        "kind": "sobol",
        "n": 32,
        "seed": 0,
        "degrees": True,
        "ranges": {"shoulder": [-10, 10], "elbow": [-10, 10]},
    },
    "springs": [
        {
            "name": "through",
            "type": "zero_free_length",
            "a": {"body": "universe", "point": [0.25, 0, -0.1]},
            "b": {"body": "link2", "point": [0.2, 0, 0.1]},
            "stiffness": {"lower": 0, "upper": 1000},
        }
    ],
    "solve": {"starts": 1, "seed": 0},
}
