"""Names that moved out of springbalance.explore.study and .report still work, with a DeprecationWarning."""

from __future__ import annotations

import types

import pytest

import springbalance.explore.study as study
from springbalance.explore import execution, report, task


@pytest.mark.parametrize(("name", "home"), [("solve_task", task), ("EXACT", task), ("CONNECT_TIMEOUT", execution)])
def test_a_moved_name_is_still_importable_from_study_and_warns(name, home):
    with pytest.warns(DeprecationWarning, match=f"study.{name} is deprecated; use {home.__name__}.{name}"):
        value = getattr(study, name)
    assert value is getattr(home, name)


def test_make_client_is_still_re_exported_by_study():
    assert study.make_client is execution.make_client


def test_write_report_of_a_study_result_still_writes_report_html_and_warns(tmp_path):
    summary = {
        "candidates": [],
        "topologies": 0,
        "orderings": 0,
        "grid_points": 1,
        "reachability": "not applied",
        "unreachable": [],
        "degenerate": [],
    }
    fake_study = types.SimpleNamespace(
        mechanism=types.SimpleNamespace(name="arm"), summary=lambda: summary, max_springs=2
    )
    result = types.SimpleNamespace(study=fake_study, folder=tmp_path, results={}, dominated=[], best=lambda: {})
    with pytest.warns(DeprecationWarning, match="write_study_report"):
        report.write_report(result)
    text = (tmp_path / "report.html").read_text()
    assert "Spring topologies of arm" in text and "No topology was solved" in text
