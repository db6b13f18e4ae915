"""Every solved topology of a study says whether its design passes every check (``ok``) and, if not, the kinds
of its failures: in results/<id>.json, results.csv, report.html and the command's summary.

The study (config_helpers.THROUGH's arm and workspace: urdf/two_link_planar_collision.urdf, both joints
±10°) has two one-spring topologies with fixed anchors, only the stiffness free:

- ``universe→link2`` is THROUGH's spring: its line crosses link1's collision box at every pose, whatever its
  stiffness (config_helpers' docstring), so it fails ``overlap``;
- ``universe→link1`` runs from 0.2 m above the shoulder to 0.3 m along link1: link1 is its own anchor body
  (exempt), and link2's box starts 0.2 m further out along link1, so nothing overlaps it; a zero-free-length
  spring from above the pivot pulls link1 up with k h r cos q against the arm's weight torque, which is
  ∝ cos q too (a small elbow angle aside), so it lowers the shoulder's torque and leaves the elbow's alone:
  no joint is made worse. It passes.
"""

from __future__ import annotations

import csv
import json

from config_helpers import THROUGH, config_file
from springbalance.cli import main


def _point_box(point: list[float]) -> dict:
    return {"lower": point, "upper": point}


def _study(folder, **sections):
    record = {
        "mechanism": THROUGH["mechanism"],
        "workspace": THROUGH["workspace"],
        "explore": {
            "candidates": [
                {
                    "a": {"body": "universe", "box": _point_box([0.25, 0, -0.1])},
                    "b": {"body": "link2", "box": _point_box([0.2, 0, 0.1])},
                },
                {
                    "a": {"body": "universe", "box": _point_box([0, 0, 0.2])},
                    "b": {"body": "link1", "box": _point_box([0.3, 0, 0])},
                },
            ],
            "max_springs": 1,
            "prune": False,
            "starts": 1,
            "seed": 0,
            "spring": {"type": "zero_free_length", "stiffness": {"lower": 0, "upper": 1000}},
            "reports": False,  # the design files only (designs/<id>.json): no page per design, faster
        },
        **sections,
    }
    return config_file(folder, record, "study.yaml")


def test_each_topology_says_whether_its_design_passes_every_check(tmp_path, capsys):
    out = tmp_path / "study"
    assert main(["explore", str(_study(tmp_path)), "--out", str(out), "--sequential"]) == 0
    summary = capsys.readouterr().out
    saved = [json.loads(path.read_text()) for path in (out / "results").glob("*.json")]
    rows = {tuple(row["springs"]): row for row in saved}
    through, lifted = rows[("universe→link2",)], rows[("universe→link1",)]
    assert through["status"] == lifted["status"] == "solved"
    assert through["ok"] is False and "overlap" in through["failures"]
    assert lifted["ok"] is True and lifted["failures"] == []
    # the saved design agrees: its failures are the row's
    assert sorted({record["kind"] for record in through["design"]["failures"]}) == through["failures"]

    table = {row["springs"]: row for row in csv.DictReader((out / "results.csv").read_text().splitlines())}
    assert table["universe→link2"]["ok"] == "False" and "overlap" in table["universe→link2"]["failures"].split()
    assert table["universe→link1"]["ok"] == "True" and table["universe→link1"]["failures"] == ""

    page = (out / "report.html").read_text()
    assert "<th>checks</th>" in page
    assert "<td>pass</td>" in page and "<td>fails: " in page and "overlap" in page.split("<td>fails: ", 1)[1]
    # the best one-spring design is the one that passes: the summary does not flag it
    assert "best with 1 spring(s): universe→link1" in summary and "FAILS" not in summary


def test_a_study_with_seeds_solves_each_topology_at_each_and_keeps_the_best(tmp_path):
    """``solve.seeds`` in a study: each topology is solved at each seed (as ``springbalance design --seeds``), its
    design is the best run's (the first that passes every check, by objective), and its row names the seed kept."""
    out = tmp_path / "study"
    study = _study(tmp_path, solve={"seeds": [2, 0, 1]})
    assert main(["explore", str(study), "--out", str(out), "--sequential"]) == 0
    rows = [json.loads(path.read_text()) for path in (out / "results").glob("*.json")]
    assert len(rows) == 2
    for row in rows:
        search = row["design"]["solver"]["seeds"]
        assert [run["seed"] for run in search["runs"]] == [2, 0, 1]
        passing = [run for run in search["runs"] if not run["failures"]] or search["runs"]
        best = min(passing, key=lambda run: run["objective"])
        assert search["kept"] == row["seed"] == best["seed"]
        assert row["objective_value"] == best["objective"]
        assert row["design"]["solver"]["seed"] == row["seed"]
