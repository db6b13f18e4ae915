"""The package's layers: data flows one way (model → springs → design → io | viz → results → cli).

`lint-imports` checks the contracts of pyproject.toml (``[tool.importlinter]``); `make test`
runs it. These tests run it on the real tree, then on a copy with one module added that closes
a loop, and expect it to fail there.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")

pytestmark = pytest.mark.skipif(
    not LINT_IMPORTS.exists(), reason="lint-imports is not installed (pip install -e '.[test]')"
)


def _lint(root: Path) -> subprocess.CompletedProcess:
    environment = {**os.environ, "PYTHONPATH": str(root / "src")}
    return subprocess.run(
        [str(LINT_IMPORTS), "--config", str(root / "pyproject.toml"), "--no-cache"],
        cwd=root,
        env=environment,
        capture_output=True,
        text=True,
        timeout=300,
    )


def _copy(tmp_path: Path) -> Path:
    shutil.copytree(ROOT / "src", tmp_path / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    return tmp_path


def test_the_tree_keeps_its_layers():
    run = _lint(ROOT)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "2 kept, 0 broken" in run.stdout


def test_a_module_that_imports_upwards_breaks_the_layers(tmp_path):
    root = _copy(tmp_path)
    # the model layer reaching up to the results closes the loop results -> design -> model -> results
    (root / "src/springbalance/model/loop.py").write_text("from springbalance.results.result import DesignResult\n")
    run = _lint(root)
    assert run.returncode != 0
    assert "springbalance.model.loop -> springbalance.results.result" in run.stdout


def test_a_cycle_inside_one_package_is_found(tmp_path):
    root = _copy(tmp_path)
    # design/problem.py imports design/evaluation.py; an evaluation-side import of problem closes a cycle
    evaluation = root / "src/springbalance/design/evaluation.py"
    evaluation.write_text(evaluation.read_text() + "\nfrom springbalance.design import problem as _loop  # noqa\n")
    run = _lint(root)
    assert run.returncode != 0
    assert "No import cycles among the modules of any package BROKEN" in run.stdout
