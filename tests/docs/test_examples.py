"""Every ```yaml and ```python block of README.md and docs/**/*.md runs.

- A YAML block that is a whole config is loaded with
  :func:`springbalance.io.config.config_from_dict` (``base_dir`` = the repository root, so that
  ``urdf/...`` paths resolve) and must validate; one with an ``explore`` section is a study
  config and must build a :class:`springbalance.explore.study.Study`. A block marked
  ``<!-- fragment -->`` on the line before it is a piece of a config: it must be valid YAML
  (read by the config loader: duplicate keys are errors).
- A Python block runs in a fresh interpreter whose working folder holds links to the
  repository's ``urdf``, ``examples``, ``docs`` and ``notebooks`` (so the examples' relative
  paths work and the files they write land in a temporary folder); a deprecated springbalance
  call in it is an error. A block marked
  ``<!-- no-run: reason -->`` (one that opens a browser, or a deliberately failing example) is
  only compiled, and the reason must be given. Running the blocks takes a while (each starts an
  interpreter and solves), so those tests are ``slow``; the markers and the syntax are checked
  in the fast tier.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from springbalance.explore.study import Study
from springbalance.io.config import config_from_dict
from springbalance.loaders import load_yaml

ROOT = Path(__file__).resolve().parents[2]
SOURCES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
LINKED = ("urdf", "examples", "docs", "notebooks")
FENCE = re.compile(r"^(?P<indent>[ \t]*)```(?P<language>[A-Za-z0-9_+-]*)[ \t]*$")
MARKER = re.compile(r"^\s*<!--\s*(?P<kind>fragment|no-run)\s*(?::\s*(?P<reason>.*?))?\s*-->\s*$")
TIMEOUT = 600  # [s] for one Python block, compile cache empty, on a loaded machine


@dataclass(frozen=True)
class Block:
    """One fenced code block of a Markdown file."""

    path: Path
    line: int  # 1-based line of the opening fence
    language: str
    code: str
    marker: str | None  # "fragment", "no-run" or None
    reason: str | None  # the text after "no-run:"

    @property
    def id(self) -> str:
        return f"{self.path.relative_to(ROOT)}:{self.line}"


def blocks(path: Path) -> list[Block]:
    """The fenced blocks of ``path``, each with the marker comment on the line before it (if any)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    found, number = [], 0
    while number < len(lines):
        opening = FENCE.match(lines[number])
        if opening is None or not opening["language"]:
            number += 1
            continue
        indent, end = opening["indent"], number + 1
        while end < len(lines) and lines[end].strip() != "```":
            end += 1
        if end == len(lines):
            raise AssertionError(f"{path.relative_to(ROOT)}:{number + 1}: code block never closed")
        code = "\n".join(line[len(indent) :] if line.startswith(indent) else line for line in lines[number + 1 : end])
        previous = next((lines[k] for k in range(number - 1, -1, -1) if lines[k].strip()), "")
        marker = MARKER.match(previous)
        found.append(
            Block(
                path,
                number + 1,
                opening["language"].lower(),
                code + "\n",
                marker["kind"] if marker else None,
                marker["reason"] if marker else None,
            )
        )
        number = end + 1
    return found


ALL = [block for path in SOURCES for block in blocks(path)]
YAML = [block for block in ALL if block.language in ("yaml", "yml")]
PYTHON = [block for block in ALL if block.language == "python"]
#: the Python blocks that run, each code once (the README's example is also Getting started's)
RUN = list({block.code: block for block in reversed(PYTHON) if block.marker != "no-run"}.values())[::-1]


def test_the_examples_are_found():
    """The collection sees the README's Python example and the config file's reference example."""
    readme = [block for block in PYTHON if block.path.name == "README.md"]
    assert readme and "sb.solve(" in readme[0].code
    assert any(block.path.name == "config.md" and block.marker is None for block in YAML)


@pytest.mark.parametrize("block", YAML, ids=[block.id for block in YAML])
def test_yaml_example_validates(block: Block):
    assert block.marker in (None, "fragment"), f"{block.id}: a YAML block takes <!-- fragment --> only"
    record = load_yaml(block.code)
    if block.marker == "fragment":
        return
    assert isinstance(record, dict), f"{block.id}: a whole config is a mapping (mark a piece <!-- fragment -->)"
    if "explore" in record:
        Study(record, base_dir=ROOT, label=block.id)
    else:
        config_from_dict(record, base_dir=ROOT, label=block.id)


@pytest.mark.parametrize("block", PYTHON, ids=[block.id for block in PYTHON])
def test_python_example_is_marked_right_and_compiles(block: Block):
    assert block.marker in (None, "no-run"), f"{block.id}: a Python block takes <!-- no-run: reason --> only"
    if block.marker == "no-run":
        assert block.reason, f"{block.id}: <!-- no-run --> needs a reason: <!-- no-run: opens a browser -->"
    compile(block.code, block.id, "exec")


@pytest.mark.slow
@pytest.mark.parametrize("block", RUN, ids=[block.id for block in RUN])
def test_python_example_runs(block: Block, tmp_path: Path):
    for name in LINKED:
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]),
        "MPLBACKEND": "Agg",
        "PYTHONWARNINGS": "error::DeprecationWarning:__main__",
    }  # no deprecated API
    process = subprocess.run(
        [sys.executable, "-c", block.code], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=TIMEOUT
    )
    assert process.returncode == 0, f"{block.id} failed:\n{process.stderr[-4000:]}"
