"""`springbalance report` and result.report(): the files, the tables' numbers, the links."""

from __future__ import annotations

import html.parser
import json
import re
from pathlib import Path

import numpy as np
import pytest

from scene_helpers import two_link_design
from springbalance.cli import main
from springbalance.results import html_report


@pytest.fixture(scope="module")
def design():
    return two_link_design()


@pytest.fixture(scope="module")
def report_folder(design, tmp_path_factory):
    folder = tmp_path_factory.mktemp("report")
    design_file = design.save(folder / "design.json")
    # a start design, not an optimum: when it fails a check, the report is written and the command exits 3
    expected = 3 if design.failures() else 0
    assert main(["report", str(design_file), "-o", str(folder / "out"), "--frames", "8"]) == expected
    return folder / "out"


class _Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.cells, self._cell = [], [], None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("href", "src"):
            if key in attrs:
                self.links.append(attrs[key])
        if tag in ("td", "th"):
            self._cell = []

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.cells.append(" ".join("".join(self._cell).split()))
            self._cell = None


def _page(folder: Path) -> _Page:
    page = _Page()
    page.feed((folder / "report.html").read_text())
    return page


def test_report_writes_every_file(report_folder, capsys):
    names = {path.name for path in report_folder.iterdir()}
    assert {"report.html", "scene.html", "torques.png", "torques.svg", "histogram.png", "histogram.svg"} <= names
    for name in ("torques.png", "histogram.png"):
        assert (report_folder / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for name in ("torques.svg", "histogram.svg"):
        assert "<svg" in (report_folder / name).read_text()[:2000]
    assert "MeshCat.Viewer" in (report_folder / "scene.html").read_text()


def test_report_links_resolve_and_nothing_is_online(report_folder):
    page = _page(report_folder)
    assert "scene.html" in page.links and "torques.svg" in page.links and "histogram.svg" in page.links
    for link in page.links:
        assert not re.match(r"(https?:)?//", link), link
        assert (report_folder / link).is_file(), link


def test_design_table_holds_the_design_values(design, report_folder):
    cells = _page(report_folder).cells
    evaluation = design.evaluation
    for column, name in enumerate(["shoulder", "forearm"]):
        record = design.spring(name)
        row = cells[cells.index(name) : cells.index(name) + 9]
        assert row[1] == "extension"
        assert f"{record['a']['body']} (" in row[2] and f"{record['b']['body']} (" in row[2]
        assert f"{record['b']['point'][0]:+.4f}" in row[2]
        assert float(row[3]) == pytest.approx(record["stiffness"], rel=1e-5)
        assert float(row[4]) == pytest.approx(record["free_length"], rel=1e-4)
        assert float(row[5]) == pytest.approx(record["initial_tension"], abs=1e-9)
        assert float(row[6]) == pytest.approx(evaluation.lengths[:, column].min(), rel=1e-3)
        assert float(row[7]) == pytest.approx(evaluation.lengths[:, column].max(), rel=1e-3)
        assert float(row[8]) == pytest.approx(np.abs(evaluation.tensions[:, column]).max(), rel=1e-3)


def test_metrics_tables_hold_the_metrics(design, report_folder):
    cells = _page(report_folder).cells
    metrics = design.metrics()
    for row in metrics["joints"]:
        start = cells.index(f"{row['joint']} [{row['unit']}]")
        values = [float(v) for v in cells[start + 1 : start + 7]]
        assert values == pytest.approx(
            [
                row["peak_before"],
                row["peak_after"],
                row["peak_reduction_percent"],
                row["rms_before"],
                row["rms_after"],
                row["rms_reduction_percent"],
            ],
            rel=2e-3,
        )
    for name, row in metrics["objectives"].items():
        start = cells.index(f"{name} [{row['unit']}]")
        if np.isfinite(row["before"]):
            assert float(cells[start + 1]) == pytest.approx(row["before"], rel=1e-3)
            assert float(cells[start + 2]) == pytest.approx(row["after"], rel=1e-3)
    assert cells[cells.index("rms [N·m]") + 4] == "optimised"


def test_report_from_python_and_without_scene(design, tmp_path):
    path = design.report(tmp_path / "a" / "b", scene=False)
    assert path == tmp_path / "a" / "b" / "report.html"
    assert not (path.parent / "scene.html").exists()
    assert "scene.html" not in _page(path.parent).links
    assert html_report.design_rows(design)[0]["where"][0][1] == "universe"


def test_report_errors_are_one_line(design, tmp_path, capsys):
    design_file = design.save(tmp_path / "design.json")
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    assert main(["report", str(design_file), "-o", str(blocker)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("springbalance: error: ") and "is a file" in err and len(err.splitlines()) == 1
    assert main(["report", str(tmp_path / "missing.json"), "-o", str(tmp_path / "out")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_report_of_a_saved_design_round_trips(design, tmp_path):
    design_file = design.save(tmp_path / "design.json")
    record = json.loads(design_file.read_text())
    status = main(["report", str(design_file), "-o", str(tmp_path / "out"), "--no-scene"])
    assert status == (3 if design.failures() else 0)
    text = (tmp_path / "out" / "report.html").read_text()
    assert record["mechanism"]["kind"] == "urdf" and "two_link_planar" in text


def test_the_views_take_the_numbers_of_a_design(design, tmp_path):
    """The views are functions of an EvaluatedDesign: a bare one (no DesignResult) gives the same report."""
    from springbalance.design.evaluated import EvaluatedDesign
    from springbalance.results import flags, report, report_plots

    bare = EvaluatedDesign(design.problem, design.x, status=design.status, method=design.method)
    assert type(bare) is EvaluatedDesign
    assert report.result_table(bare) == design.table()
    assert flags.flags(bare) == design.warnings()
    assert html_report.report_html(bare) == html_report.report_html(design)
    page = html_report.write_report(bare, tmp_path / "bare", scene=False).read_text()
    figures = report_plots.write_plots(bare, tmp_path / "bare")  # the further plots: here the spread only
    assert [figure.file for figure in figures] == ["spread.svg"]
    assert page == html_report.report_html(bare, scene=None, exports=[], figures=figures)
