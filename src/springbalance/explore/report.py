"""The report of a study: ``report.html`` with the Pareto front and every topology's fate.

The plot puts each solved topology at its number of springs (or, when every spring has a mass,
the springs' total mass [kg]) against its residual peak relative to the unbalanced peak (log
scale); buildable designs (every spring a helical coil whose spec sheet passes) are filled, the
others hollow, and the front (no other design has
fewer springs and a smaller residual) is joined by a line. The tables list the best design of
each spring count (with its design file), every solved topology (with whether its design passes every
check of :meth:`~springbalance.results.result.DesignResult.failures`, or which kinds it fails), and the
topologies that were not solved and why (proven unreachable, degenerate, dominated by an exact subset, failed).
"""

from __future__ import annotations

import html
import io
import json
from pathlib import Path
from typing import Any, Callable, Mapping

from springbalance.deprecation import warn_deprecated
from springbalance.files import write_text_atomic


def pareto_svg(records: list[dict]) -> str:
    """The Pareto plot (SVG text) of the solved ``records``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    by_mass = bool(records) and all(record.get("spring_mass") is not None for record in records)
    x = [record["spring_mass"] if by_mass else record["count"] for record in records]
    y = [max(record["relative_residual"], 1e-16) for record in records]
    figure, axes = plt.subplots(figsize=(6.4, 4.0))
    for buildable, marker in ((True, "o"), (False, "o")):
        points = [(a, b) for a, b, record in zip(x, y, records) if bool(record.get("buildable")) == buildable]
        if points:
            xs, ys = zip(*points)
            axes.scatter(
                xs,
                ys,
                s=36,
                marker=marker,
                facecolors="C0" if buildable else "none",
                edgecolors="C0",
                label="buildable (every spring a coil that passes its spec sheet)"
                if buildable
                else "not shown buildable (ideal laws, or a spec sheet fails)",
            )
    front, best = [], float("inf")
    for a, b in sorted(zip(x, y)):
        if b < best:
            front.append((a, b))
            best = b
    if front:
        axes.plot(*zip(*front), color="C1", linewidth=1.2, label="Pareto front")
    axes.set_yscale("log")
    axes.set_xlabel("total spring mass [kg]" if by_mass else "number of springs")
    axes.set_ylabel("peak residual / unbalanced peak [1]")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(loc="best", fontsize=8)
    figure.tight_layout()
    stream = io.StringIO()
    figure.savefig(stream, format="svg")
    plt.close(figure)
    text = stream.getvalue()
    return text[text.index("<svg") :]


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


def _not_solved(summary: Mapping[str, Any], dominated: list[dict], failed: list[dict]) -> list[dict]:
    """The topologies that were not solved, each with why."""
    return (
        [{**item, "why": "proven unreachable: " + item["reason"]} for item in summary["unreachable"]]
        + [{**item, "why": "degenerate: " + item["reason"]} for item in summary["degenerate"]]
        + [{**item, "why": "dominated: " + " + ".join(item["because"]) + " balances exactly"} for item in dominated]
        + [{**item, "why": "failed: " + item.get("error", "")} for item in failed]
    )


def write_study_report(
    folder: str | Path,
    mechanism_name: str,
    summary: Mapping[str, Any],
    max_springs: int,
    results: Mapping[str, dict],
    dominated: list[dict],
    best: Mapping[int, dict],
) -> None:
    """Write ``report.html`` into the study ``folder``.

    ``summary`` is the study's enumeration and pruning (``Study.summary()``: candidates, topology
    and grid counts, unreachable and degenerate topologies), ``results`` every task's result by id,
    ``dominated`` the topologies skipped because a subset balances exactly, ``best`` the best solved
    task per spring count (``StudyResult.best()``).
    """
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
        pareto_svg(solved) if solved else "<p>No topology was solved.</p>",
        "<h2>Best design per spring count</h2>",
        _rows(
            [{**record, "file": f"best_{count}_springs.json"} for count, record in best.items()],
            [*_TOPOLOGY, *_VERDICT, ("design file", lambda r: r["file"])],
        ),
        "<h2>Solved topologies</h2>",
        _rows(
            solved,
            [
                *_TOPOLOGY,
                ("objective", lambda r: f"{r['objective']} {r['objective_value']:.4g}"),
                *_VERDICT,
                ("time [s]", lambda r: f"{r['seconds']:.1f}"),
            ],
        ),
        "<h2>Not solved</h2>",
        _rows(_not_solved(summary, dominated, failed), [*_TOPOLOGY, ("why", lambda r: r["why"])]),
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
