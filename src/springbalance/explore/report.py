"""The report of a study: ``report.html`` with the Pareto front and every topology's fate.

The plot (:mod:`springbalance.explore.pareto`) puts each solved topology at its number of springs (or,
when every spring has a mass, the springs' total mass [kg]) against its residual peak relative to the
unbalanced peak (log scale), draws the front (no other design has fewer springs and a smaller residual),
and links each point to its design's report (``designs/<id>/report.html``). The tables list the best
design of each spring count, every count from 1 to ``max_springs`` (with its report and design file; a
count that pruning left unsolved gives the best of its few pruned topologies solved for an approximate
design, :mod:`springbalance.explore.approximate`, or says why it has none), every solved topology (with
whether its design passes every check of :meth:`~springbalance.results.result.DesignResult.failures`, or
which kinds it fails), and the topologies that were not solved and why (proven unreachable, degenerate,
dominated by an exact subset, failed).
"""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any, Callable, Mapping

from springbalance.deprecation import warn_deprecated
from springbalance.explore.approximate import DEFAULT as DEFAULT_APPROXIMATE
from springbalance.explore.approximate import why_not
from springbalance.explore.pareto import pareto_svg
from springbalance.explore.pseudo_base_proposals import proposals_html
from springbalance.files import write_text_atomic

__all__ = ["checks", "pareto_svg", "write_report", "write_study_report"]


def _rows(records: list[dict], columns: list[tuple[str, Callable[[dict], Any]]]) -> str:
    head = "".join(f"<th>{html.escape(title)}</th>" for title, _ in columns)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(str(cell(record)))}</td>" for _, cell in columns) + "</tr>"
        for record in records
    )
    return f"<table><tr>{head}</tr>{body}</table>"


def checks(record: dict) -> str:
    """A solved topology's verdict: "pass" when its design passes every check, else "fails: " and the kinds
    of its failures ("" for a result of an earlier version, which did not record it)."""
    if "ok" not in record:
        return ""
    return "pass" if record["ok"] else "fails: " + ", ".join(record.get("failures", []))


#: the columns that name a topology: its springs and its grid point
_TOPOLOGY: list[tuple[str, Callable[[dict], Any]]] = [
    ("springs", lambda r: " + ".join(r.get("springs", []))),
    ("grid", lambda r: json.dumps(r.get("grid", {}), sort_keys=True) if r.get("grid") else ""),
]
#: the columns that judge a solved topology's design
_VERDICT: list[tuple[str, Callable[[dict], Any]]] = [
    ("residual / unbalanced", lambda r: f"{r['relative_residual']:.3g}"),
    ("exact", lambda r: "yes" if r["exact"] else ""),
    ("buildable", lambda r: "yes" if r["buildable"] else ""),
    ("checks", checks),
]


def _not_solved(
    summary: Mapping[str, Any], dominated: list[dict], failed: list[dict], solved: list[dict]
) -> list[dict]:
    """The topologies that were not solved, each with why (a pruned one solved for an approximate design is
    solved)."""
    done = {frozenset(record["springs"]) for record in solved}
    pruned = [
        {**item, "why": f"{why}: " + item["reason"]}
        for key, why in (("unreachable", "proven unreachable"), ("degenerate", "degenerate"))
        for item in summary[key]
        if frozenset(item["springs"]) not in done
    ]
    return (
        pruned
        + [{**item, "why": "dominated: " + " + ".join(item["because"]) + " balances exactly"} for item in dominated]
        + [{**item, "why": "failed: " + item.get("error", "")} for item in failed]
    )


def _link(href: str | None, text: str) -> str:
    return f'<a href="{html.escape(href)}">{html.escape(text)}</a>' if href else ""


def _best_rows(
    best: Mapping[int, dict],
    max_springs: int,
    summary: Mapping[str, Any],
    links: Mapping[str, str],
    approximate: int,
) -> str:
    """The table of the best design of each spring count 1 … ``max_springs``: how it was found (solved for
    exact balance, or the best of the pruned few solved for an approximate design), its verdict and its
    pages; a count without a design says why."""
    head = ["springs", "found", "residual / unbalanced", "exact", "buildable", "checks", "report", "design file"]
    rows = []
    pruned: dict[int, int] = {}
    for item in summary["unreachable"] + summary["degenerate"]:
        pruned[len(item["springs"])] = pruned.get(len(item["springs"]), 0) + 1
    for count in range(1, max_springs + 1):
        record = best.get(count)
        if record is None:
            why = why_not(count, len(summary["candidates"]), approximate, pruned.get(count, 0))
            rows.append(f"<tr><td>{count} spring(s)</td><td colspan={len(head) - 1}>{html.escape(why)}</td></tr>")
            continue
        found = (
            "approximate: the best screened topology (none of this count found exact)"
            if record.get("pruned", "").startswith("screened")
            else f"approximate: the best of the pruned topologies solved ({record['pruned'].split(':')[0]})"
            if record.get("pruned")
            else "solved"
        )
        report = links.get(record["id"], "")
        cells = [
            html.escape(" + ".join(record.get("springs", []))),
            html.escape(found),
            *(html.escape(str(cell(record))) for _, cell in _VERDICT),
            _link(report, "report") if report.endswith(".html") else "",
            _link(f"best_{count}_springs.json", f"best_{count}_springs.json"),
        ]
        rows.append("<tr>" + "".join(f"<td>{cell}</td>" for cell in cells) + "</tr>")
    return "<table><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>" + "".join(rows) + "</table>"


def _screening(counts: Mapping[str, dict] | None) -> str:
    """The fewest-springs search per count (:mod:`springbalance.explore.screening`): proven, not found, exact."""
    if not counts:
        return ""
    head = ["springs", "topologies", "proven unreachable", "screened, not found", "exact", "best residual", "time [s]"]
    rows = [
        [
            str(item["count"]),
            str(item["topologies"]),
            str(item["unreachable"]),
            str(item["not_found"]),
            (
                f"{len(item['exact'])} springs by elimination (an upper bound; not screened): "
                if item.get("eliminated")
                else ""
            )
            + (" + ".join(item["exact"]) or "none found"),
            f"{item['best_relative']:.3g}",
            f"{item['seconds']:.1f}",
        ]
        for item in counts.values()
    ]
    return (
        "<h2>Fewest springs</h2><p>Spring counts from 1 up to the first with an exact design; each unproven topology "
        "screened on the exact coefficients (anchors in their boxes). <em>Screened, not found</em> is not a proof: "
        "the proven ones are counted apart. Best residual: the largest coefficient left over gravity's.</p>"
        + "<table><tr>"
        + "".join(f"<th>{h}</th>" for h in head)
        + "</tr>"
        + "".join("<tr>" + "".join(f"<td>{html.escape(cell)}</td>" for cell in row) + "</tr>" for row in rows)
        + "</table>"
    )


def write_study_report(
    folder: str | Path,
    mechanism_name: str,
    summary: Mapping[str, Any],
    max_springs: int,
    results: Mapping[str, dict],
    dominated: list[dict],
    best: Mapping[int, dict],
    links: Mapping[str, str] | None = None,
    approximate: int = DEFAULT_APPROXIMATE,
) -> None:
    """Write ``report.html`` into the study ``folder``.

    ``summary`` is the study's enumeration and pruning (``Study.summary()``: candidates, topology
    and grid counts, unreachable and degenerate topologies), ``results`` every task's result by id,
    ``dominated`` the topologies skipped because a subset balances exactly, ``best`` the best solved
    task per spring count (``StudyResult.best()``), ``links`` each solved task's page by id (relative to
    ``folder``: its report or design file, :func:`springbalance.explore.designs.write_designs`), and
    ``approximate`` the study's ``explore.approximate``.
    """
    links = links or {}
    solved = sorted(
        (r for r in results.values() if r.get("status") == "solved"), key=lambda r: (r["count"], r["relative_residual"])
    )
    failed = [r for r in results.values() if r.get("status") != "solved"]
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'><title>springbalance study</title>",
        "<style>body{font-family:sans-serif;margin:2em;max-width:70em}table{border-collapse:collapse;margin:1em 0}"
        "td,th{border:1px solid #ccc;padding:0.2em 0.6em;font-size:0.9em}th{background:#eee}</style></head><body>",
        f"<h1>Spring topologies of {html.escape(mechanism_name)}</h1>",
        f"<p>{len(summary['candidates'])} candidates, up to {max_springs} springs: {summary['topologies']} "
        f"topologies ({summary['orderings']} orderings of springs, counted once each) × {summary['grid_points']} "
        f"grid point(s). {html.escape(summary['reachability'])}: {len(summary['unreachable'])} proven unreachable, "
        f"{len(summary['degenerate'])} degenerate; {len(dominated)} dominated by an exactly balancing subset; "
        f"{len(solved)} solved, {len(failed)} failed.</p>",
        "<h2>Pareto front</h2>",
        "<p>Each solved topology is a point; the front (ringed, joined by its staircase) holds the designs that "
        "no other beats with as few springs (as light springs). Click a point to open its design's report.</p>"
        if solved
        else "",
        pareto_svg(solved, links) if solved else "<p>No topology was solved.</p>",
        _screening(summary.get("screening")),
        "<h2>Best design per spring count</h2>",
        _best_rows(best, max_springs, summary, links, approximate),
        "<h2>Solved topologies</h2>",
        _rows(
            solved,
            [
                *_TOPOLOGY,
                ("pruned", lambda r: r.get("pruned", "").split(":")[0]),
                ("objective", lambda r: f"{r['objective']} {r['objective_value']:.4g}"),
                *_VERDICT,
                ("time [s]", lambda r: f"{r['seconds']:.1f}"),
            ],
        ),
        "<h2>Not solved</h2>",
        _rows(_not_solved(summary, dominated, failed, solved), [*_TOPOLOGY, ("why", lambda r: r["why"])]),
        proposals_html(summary.get("pseudo_base_proposals", [])),
        "</body></html>",
    ]
    write_text_atomic(Path(folder) / "report.html", "\n".join(parts))


def write_report(result: Any) -> None:
    """Deprecated: write ``report.html`` of a ``StudyResult`` (use :func:`write_study_report`, or
    ``StudyResult.write``)."""
    warn_deprecated(
        "springbalance.explore.report.write_report(result)",
        "write_study_report(folder, mechanism_name, summary, max_springs, results, dominated, best) "
        "or StudyResult.write()",
    )
    study = result.study
    write_study_report(
        result.folder,
        study.mechanism.name,
        study.summary(),
        study.max_springs,
        result.results,
        result.dominated,
        result.best(),
    )
