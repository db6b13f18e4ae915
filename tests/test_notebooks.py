"""The notebooks in notebooks/ run top to bottom (nbclient, a fresh kernel each) without errors.

They run on copies in a temporary folder that mirrors the repository's layout (``urdf`` and
``examples`` next to ``notebooks``), so what they write (``out/...``) stays out of the
repository. They use only local files: no server, no network.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


def test_there_are_three_notebooks_stored_without_outputs():
    assert [path.name for path in NOTEBOOKS] == [
        "01_quick_start_single_link.ipynb",
        "02_ur5_four_springs.ipynb",
        "03_comparing_objectives.ipynb",
    ]
    for path in NOTEBOOKS:
        notebook = nbformat.read(path, as_version=4)
        nbformat.validate(notebook)
        for cell in notebook.cells:
            if cell.cell_type == "code":
                assert cell.outputs == [] and cell.execution_count is None, f"{path.name} is stored with outputs"


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    folder = tmp_path_factory.mktemp("repository")
    for name in ("urdf", "examples"):
        (folder / name).symlink_to(ROOT / name, target_is_directory=True)
    (folder / "notebooks").mkdir()
    return folder / "notebooks"


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[path.stem for path in NOTEBOOKS])
def test_notebook_runs_top_to_bottom(path, workspace):
    copy = workspace / path.name
    shutil.copy(path, copy)
    notebook = nbformat.read(copy, as_version=4)
    client = nbclient.NotebookClient(
        notebook, timeout=240, kernel_name="python3", resources={"metadata": {"path": str(workspace)}}
    )
    start = time.monotonic()
    client.execute()  # raises CellExecutionError, with the cell and its traceback, on any error
    elapsed = time.monotonic() - start
    assert elapsed < 120, f"{path.name} took {elapsed:.0f} s"
    outputs = [output for cell in notebook.cells if cell.cell_type == "code" for output in cell.outputs]
    assert not [output for output in outputs if output.output_type == "error"]
    # figures came out as images, not as "<Figure size ...>" text
    assert any("image/png" in output.get("data", {}) for output in outputs), "no figure was drawn"
