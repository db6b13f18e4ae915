"""Fuzz of the command line with randomly mutated configs and URDFs (issue 15).

A seeded generator (reproducible: :data:`SEED`) writes :data:`CONFIG_CASES` mutated config files
(YAML or JSON: a leaf set to a hostile value, a key deleted, added or repeated, the text truncated
or garbled, an alias bomb), :data:`URDF_CASES` mutated URDFs (a numeric attribute set to
``nan``, ``-2``, ``1e400``, ``abc``, ...; an element removed; a joint of an unknown type; the text
truncated) and :data:`DESIGN_CASES` mutated design files. Each goes through ``springbalance
design`` (configs, and some URDFs through a config), ``springbalance inspect`` (the other URDFs)
or ``springbalance evaluate`` / ``export`` (design files), run in-process through
:func:`springbalance.cli.main`. The command line must never let an exception out (what would be
a traceback), never print ``Traceback``, and exit only with 0, 1 or 2. The workspaces are tiny
(8 samples) and the solves short, so that the whole fuzz takes well under 2 minutes.
"""

from __future__ import annotations

import copy
import json
import random
import time
from pathlib import Path

import pytest
import yaml

from config_helpers import SHOULDER_SPRING
from springbalance.cli import main

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf" / "two_link_planar.urdf"
SEED = 15
CONFIG_CASES = 130
URDF_CASES = 90
DESIGN_CASES = 40
TIME_BUDGET = 120.0  # [s], the whole fuzz

BASE = {
    "mechanism": {"urdf": str(URDF)},
    "workspace": {
        "kind": "sobol",
        "n": 8,
        "seed": 0,
        "degrees": True,
        "ranges": {"shoulder": [-90, 90], "elbow": [0, 0]},
    },
    "springs": [SHOULDER_SPRING],
    "objective": "rms",
    "weights": {"elbow": 0.0},
    "solve": {"starts": 1, "seed": 0, "max_iterations": 10},
}

HOSTILE_VALUES = [
    -1,
    0,
    1,
    2.5,
    -1e-300,
    1e20,
    10**30,
    1e308,
    float("nan"),
    float("inf"),
    -float("inf"),
    True,
    False,
    None,
    "",
    "x",
    "nan",
    "1e400",
    "../../etc/passwd",
    [],
    {},
    [1, 2, 3],
    [[1, 2], [3]],
    {"lower": 1, "upper": 0},
    {"lower": 0, "upper": 1},
    {"kind": "grid", "n": 100000},
    {"kind": "sweep", "joint": "elbow", "n": 1000000000},
    {"kind": "sobol", "n": 1e20},
    "universe",
    "link1",
    "shoulder",
    "ur5",
    [0, 0, 0],
    {"body": "link1"},
]
HOSTILE_NUMBERS = [
    "nan",
    "-2",
    "inf",
    "-inf",
    "1e400",
    "",
    "abc",
    "1 2",
    "0",
    "-0",
    "1e-300",
    "1e300",
    "0x10",
    " 1",
    "1,5",
    "+.5",
    "1e",
    "--1",
    "2 3 4 5",
    "NaN",
    "1_0",
]


# ---------------------------------------------------------------------- config mutations
def leaves(node, path=()):
    """Key paths of every value in ``node`` (mappings and lists walked)."""
    found = [path] if path else []
    if isinstance(node, dict):
        for key, value in node.items():
            found += leaves(value, (*path, key))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            found += leaves(value, (*path, index))
    return found


def parent_of(record, path):
    node = record
    for step in path[:-1]:
        node = node[step]
    return node


def mutate_record(rng: random.Random, record: dict) -> dict:
    record = copy.deepcopy(record)
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        paths = leaves(record)
        if not paths:
            break
        path = rng.choice(paths)
        parent, key = parent_of(record, path), path[-1]
        action = rng.random()
        if action < 0.6:
            parent[key] = copy.deepcopy(rng.choice(HOSTILE_VALUES))
        elif action < 0.8 and isinstance(parent, dict):
            del parent[key]
        elif isinstance(parent, dict):
            parent[rng.choice(["nn", "kind", "extra", "min_length", "max_length", "max_force", "validate"])] = (
                copy.deepcopy(rng.choice(HOSTILE_VALUES))
            )
        else:
            parent.append(copy.deepcopy(rng.choice(HOSTILE_VALUES)))
    return record


def config_text(rng: random.Random) -> tuple[str, str]:
    """(file name, text) of one mutated config."""
    record = mutate_record(rng, BASE)
    kind = rng.random()
    if kind < 0.3:
        text = json.dumps(record, allow_nan=True)
        name = "config.json"
    else:
        text = yaml.safe_dump(record, sort_keys=False, allow_unicode=True)
        name = "config.yaml"
    damage = rng.random()
    if damage < 0.12:
        text = text[: rng.randrange(len(text) + 1)]  # truncated
    elif damage < 0.22:
        position = rng.randrange(len(text) + 1)  # garbled
        text = (
            text[:position]
            + rng.choice(["{", "]", ":", "&a", "*a", "\t", "\x00", "é", "'", '"', "- -"])
            + text[position:]
        )
    elif damage < 0.3 and name.endswith(".yaml"):
        text += rng.choice(["mechanism: {robot: ur5}\n", "springs: []\n", "solve: {starts: 2}\n"])  # a key twice
    elif damage < 0.35 and name.endswith(".yaml"):
        text = (
            "a: &a [1, 2, 3, 4, 5, 6, 7, 8, 9]\n"
            + "".join(f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 9)}]\n" for i in range(8))
            + text
        )
    return name, text


# ---------------------------------------------------------------------- URDF mutations
URDF_ATTRIBUTES = [
    ('<mass value="2.0"/>', 'value="2.0"'),
    ('<mass value="1.0"/>', 'value="1.0"'),
    ('ixx="0.0005"', 'ixx="0.0005"'),
    ('iyy="0.042"', 'iyy="0.042"'),
    ('izz="0.0135"', 'izz="0.0135"'),
    ('ixy="0"', 'ixy="0"'),
    ('lower="-1.5707963267948966"', 'lower="-1.5707963267948966"'),
    ('upper="2.6179938779914944"', 'upper="2.6179938779914944"'),
    ('effort="50"', 'effort="50"'),
    ('velocity="3"', 'velocity="3"'),
    ('<origin xyz="0.5 0 0" rpy="0 0 0"/>', 'xyz="0.5 0 0"'),
    ('<origin xyz="0.25 0 0" rpy="0 0 0"/>', 'rpy="0 0 0"'),
    ('<axis xyz="0 -1 0"/>', 'xyz="0 -1 0"'),
    ('<box size="0.5 0.04 0.04"/>', 'size="0.5 0.04 0.04"'),
    ('<sphere radius="0.03"/>', 'radius="0.03"'),
]
URDF_EDITS = [
    ('type="revolute"', 'type="floating"'),
    ('type="revolute"', 'type="planar"'),
    ('type="revolute"', 'type="hinge"'),
    ('type="fixed"', 'type="continuous"'),
    ('<child link="link2"/>', '<child link="nowhere"/>'),
    ('<parent link="link1"/>', '<parent link="link1"/><parent link="base"/>'),
    ('<link name="base"/>', ""),
    ('<robot name="two_link_planar">', "<robot>"),
    ('<robot name="two_link_planar">', '<robt name="x">'),
    ("<inertial>", '<inertial><mass value="3"/>'),
    ('<mass value="2.0"/>', ""),
    ('lower="-1.5707963267948966" upper="1.5707963267948966"', 'lower="1.5707963267948966" upper="-1.5"'),
    ('<limit lower="-1.5707963267948966" upper="1.5707963267948966" effort="50" velocity="3"/>', ""),
    ('<axis xyz="0 -1 0"/>', '<axis xyz="0 0 0"/>'),
    ('iyy="0.042"', 'iyy="0.001"'),
]


def urdf_text(rng: random.Random) -> str:
    text = URDF.read_text()
    for _ in range(rng.choice([1, 1, 2])):
        choice = rng.random()
        if choice < 0.6:
            element, attribute = rng.choice(URDF_ATTRIBUTES)
            name, _, _ = attribute.partition("=")
            changed = element.replace(attribute, f'{name}="{rng.choice(HOSTILE_NUMBERS)}"')
            text = text.replace(element, changed, 1)
        elif choice < 0.9:
            old, new = rng.choice(URDF_EDITS)
            text = text.replace(old, new, 1)
        else:
            text = text[: rng.randrange(len(text) + 1)]
    return text


# ---------------------------------------------------------------------- the fuzz
def run(argv, capsys) -> tuple[int | None, str]:
    """Exit status of ``main(argv)`` and a problem description (empty when it behaved)."""
    try:
        code = main(argv)
    except SystemExit as stop:  # argparse's usage errors
        code = stop.code
    except BaseException as error:
        capsys.readouterr()
        return None, f"{type(error).__name__}: {error}"
    captured = capsys.readouterr()
    if "Traceback" in captured.err or "Traceback" in captured.out:
        return code, f"printed a traceback: {captured.err[-500:]}"
    if code not in (0, 1, 2, 3):
        return code, f"exit status {code}: {captured.err[-300:]}"
    if code == 3 and "springbalance: failure: " not in captured.err:  # a design that fails a check says which
        return code, f"exit status 3 without a failure line: {captured.err[-300:]}"
    if code == 2 and not captured.err.strip():
        return code, "exit status 2 without a message"
    return code, ""


def test_fuzzed_configs_urdfs_and_designs_never_crash_the_command_line(tmp_path, capsys):
    rng = random.Random(SEED)
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(BASE))
    assert main(["design", str(tmp_path / "base.yaml"), "--out", str(tmp_path / "base.json"), "--quiet"]) == 0
    design = json.loads((tmp_path / "base.json").read_text())
    start = time.perf_counter()
    problems, codes = [], {}
    total = CONFIG_CASES + URDF_CASES + DESIGN_CASES
    for index in range(total):
        folder = tmp_path / f"case{index}"
        folder.mkdir()
        out = folder / "design.json"
        if index >= CONFIG_CASES + URDF_CASES:
            (folder / "damaged.json").write_text(json.dumps(mutate_record(rng, design), allow_nan=True))
            argv = rng.choice(
                [
                    ["evaluate", str(folder / "damaged.json")],
                    ["export", str(folder / "damaged.json"), "--mjcf", str(folder / "arm.xml")],
                ]
            )
            what = f"design {index}: {argv[0]}"
        elif index < CONFIG_CASES:
            name, text = config_text(rng)
            (folder / name).write_text(text, encoding="utf-8", errors="surrogateescape")
            argv = ["design", str(folder / name), "--out", str(out), "--quiet"]
            what = f"config {index}: {text[:300]!r}"
        else:
            text = urdf_text(rng)
            (folder / "arm.urdf").write_text(text)
            if rng.random() < 0.3:  # through a config, as design reads it
                record = copy.deepcopy(BASE)
                record["mechanism"] = {"urdf": "arm.urdf", "validate": rng.random() < 0.8}
                (folder / "config.yaml").write_text(yaml.safe_dump(record))
                argv = ["design", str(folder / "config.yaml"), "--out", str(out), "--quiet"]
            else:
                argv = ["inspect", str(folder / "arm.urdf")] + (["--no-validate"] if rng.random() < 0.3 else [])
            what = f"URDF {index}: {argv[0]}"
        code, problem = run(argv, capsys)
        codes[code] = codes.get(code, 0) + 1
        if problem:
            problems.append(f"{what}: {problem}")
    elapsed = time.perf_counter() - start
    print(f"fuzz: {total} cases in {elapsed:.1f} s, exit statuses {codes}")
    assert not problems, "\n".join(problems[:10])
    assert CONFIG_CASES + URDF_CASES >= 200
    assert codes.get(2, 0) > 100 and codes.get(0, 0) > 0  # mostly refused, some still designed
    assert elapsed < TIME_BUDGET


@pytest.mark.parametrize("index", range(3))
def test_the_generator_is_reproducible(index):
    first, second = random.Random(SEED + index), random.Random(SEED + index)
    assert config_text(first) == config_text(second) and urdf_text(first) == urdf_text(second)
