"""Each solved design of a study as files of its own, so that the study's report can link to it.

For a solved task ``<id>`` the study folder gets ``designs/<id>.json`` (its design file, which every
command accepts) and, when ``explore.reports`` is true (the default), ``designs/<id>/report.html``: the
design's report (:func:`springbalance.results.html_report.write_report`, without the 3-D scene, which
``springbalance report designs/<id>.json`` adds). A file that exists is not written again: a resumed
study only writes the designs it solved since (a task's id is a hash of its config, so its design is
the same).
"""

from __future__ import annotations

from pathlib import Path
from typing import Mapping

from springbalance.files import write_json_atomic
from springbalance.results.html_report import write_report
from springbalance.results.result import DesignResult

#: the study folder's subfolder of design files and reports
FOLDER = "designs"


def design_file(record: Mapping) -> str:
    """The design file of a solved task, relative to the study folder."""
    return f"{FOLDER}/{record['id']}.json"


def design_report(record: Mapping) -> str:
    """The report of a solved task, relative to the study folder."""
    return f"{FOLDER}/{record['id']}/report.html"


def write_designs(folder: Path, records: Mapping[str, dict], reports: bool = True) -> dict[str, str]:
    """Write each solved record's design file (and report when ``reports``) into ``folder`` (see the module);
    returns, by id, the address (relative to ``folder``) of the page its point links to: the report, or
    the design file without reports."""
    links = {}
    for task_id, record in records.items():
        if record.get("status") != "solved" or not record.get("design"):
            continue
        path = folder / design_file(record)
        if not path.exists():
            write_json_atomic(path, record["design"])
        links[task_id] = design_file(record)
        if not reports:
            continue
        page = folder / design_report(record)
        if not page.exists():
            write_report(DesignResult.load(path), page.parent, scene=False)
        links[task_id] = design_report(record)
    return links
