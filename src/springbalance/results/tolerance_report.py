"""The tolerance section of the reports (text and HTML): the worst residual over the springs' tolerance box and
each spring's adjuster travel (:mod:`springbalance.design.tolerance`, docs/model.md §3.10).

Per joint: the nominal peak and RMS, the worst case over the box (the envelope's peak, which some build
reaches, and its RMS, which bounds every build's), and the same after re-balancing each build with its
adjusters. Per spring: its ± (rate in %, initial tension or preload in N, free length in mm) and the
preload-screw travel [mm] that restores the balance over the box.
"""

from __future__ import annotations

import html
from typing import Any

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.tolerance import ToleranceAnalysis, analyse_tolerance


def tolerance_analysis(result: EvaluatedDesign) -> ToleranceAnalysis | None:
    """The design's tolerance analysis under its spec (grade 2 by default), or None when no spring has a box."""
    analysis = analyse_tolerance(result, result.tolerance)
    return analysis if analysis.boxes else None


def tolerance_record(result: EvaluatedDesign) -> dict[str, Any]:
    """``{"tolerance": …}`` for ``design.json`` (empty when no spring has a box)."""
    analysis = tolerance_analysis(result)
    return {"tolerance": analysis.to_dict()} if analysis is not None else {}


def _spring_rows(analysis: ToleranceAnalysis) -> list[list[str]]:
    rows = []
    for box, travel in zip(analysis.boxes, analysis.travel):
        rows.append(
            [
                box.name,
                box.source,
                f"±{100 * box.d_rate:.3g} %",
                f"±{box.d_tension:.3g} N",
                f"±{1e3 * box.d_free_length:.3g} mm",
                f"{1e3 * travel['low']:+.2f} … {1e3 * travel['high']:+.2f} mm",
                f"{1e3 * travel['travel']:.2f} mm",
            ]
        )
    return rows


_SPRING_HEAD = ["spring", "tolerance", "rate", "F_i / preload", "free length", "adjustment", "travel"]


def tolerance_lines(result: EvaluatedDesign) -> list[str]:
    """The "Tolerances" section of the text report (empty when no spring has a box)."""
    analysis = tolerance_analysis(result)
    if analysis is None:
        return []
    lines = ["Tolerances: worst case over the springs' tolerance box (exact over all corners; RMS an upper bound)"]
    lines.append(
        f"  {'joint':<22s}{'peak':>10s}{'worst peak':>12s}{'rms':>10s}{'worst rms':>11s}"
        f"{'adjusted peak':>15s}{'adjusted rms':>14s}"
    )
    for row in analysis.joints:
        lines.append(
            f"  {row['joint'] + ' [' + row['unit'] + ']':<22s}{row['peak']:10.4g}{row['worst_peak']:12.4g}"
            f"{row['rms']:10.4g}{row['worst_rms']:11.4g}{row['adjusted_peak']:15.4g}{row['adjusted_rms']:14.4g}"
        )
    table = [_SPRING_HEAD, *_spring_rows(analysis)]
    widths = [max(len(line[column]) for line in table) for column in range(len(_SPRING_HEAD))]
    lines += ["  " + "  ".join(cell.ljust(w) for cell, w in zip(line, widths)).rstrip() for line in table]
    bound = analysis.spec.adjuster_travel
    if bound is not None:
        over = [row["name"] for row in analysis.travel if row["travel"] > bound]
        verdict = f"EXCEEDED by {', '.join(over)}" if over else "every spring within it"
        lines.append(f"  adjuster travel bound {1e3 * bound:.2f} mm: {verdict}")
    lines.append(
        "  adjuster: a preload screw in series with each spring shortens its effective free length by t "
        "(t > 0 stretches an extension spring, compresses a compression spring); t: the least-squares turn that "
        "brings a build back to the nominal design (0 for the nominal build); travel = its range over the box"
    )
    return lines + _corner_lines(analysis) + [""]


def _corner_head(analysis: ToleranceAnalysis) -> list[str]:
    adjusted = "adjusters" in analysis.corners[0]
    names = list(analysis.corners[0].get("adjusters", {}))
    return ["case", "peak [N·m]", "rms [N·m]", *(f"t {name} [mm]" for name in names), *(["travel"] if adjusted else [])]


def _corner_rows(analysis: ToleranceAnalysis) -> list[list[str]]:
    rows = []
    for row in analysis.corners:
        cells = [row["name"], f"{row['peak']:.4g}", f"{row['rms']:.4g}"]
        if "adjusters" in row:
            cells += [f"{1e3 * t:+.2f}" for t in row["adjusters"].values()]
            cells.append("AT BOUND: " + ", ".join(row["at_bound"]) if row["at_bound"] else "within")
        rows.append(cells)
    return rows


def _corner_lines(analysis: ToleranceAnalysis) -> list[str]:
    """The robust design's cases: each corner's residual and adjuster settings (nothing for a nominal design)."""
    if not analysis.corners:
        return []
    spec = analysis.spec
    worst = max(row["rms"] for row in analysis.corners)
    lines = [
        f"  robust design over {len(analysis.corners) - 1} corners ({spec.corners}; k±: rate, F±: a stronger/weaker "
        f"spring), worst case RMS {worst:.4g} N·m"
        + (
            ""
            if spec.adjuster_travel is None
            else f"; each corner re-balanced by its adjusters within ±{1e3 * spec.adjuster_travel:.2f} mm"
        )
    ]
    table = [_corner_head(analysis), *_corner_rows(analysis)]
    widths = [max(len(line[column]) for line in table) for column in range(len(table[0]))]
    lines += ["  " + "  ".join(cell.ljust(w) for cell, w in zip(line, widths)).rstrip() for line in table]
    if spec.adjuster_travel is not None:
        short = sorted({name for row in analysis.corners for name in row["at_bound"]})
        lines.append(
            "  the travel suffices: no setting reaches it"
            if not short
            else f"  the travel limits the re-balancing of {', '.join(short)}: a longer travel lowers the worst case"
        )
    return lines


def tolerance_html(result: EvaluatedDesign) -> list[str]:
    """The "Tolerances" section of ``report.html`` (nothing when no spring has a box)."""
    analysis = tolerance_analysis(result)
    if analysis is None:
        return []
    e = html.escape
    parts = [
        '<h2 id="tolerances">Tolerances</h2>',
        "<p>Worst case over the springs' tolerance box (exact over all corners; the RMS bounds every build's), "
        "and after each build's preload screws bring it back to the nominal design (the nominal build needs no "
        "turn).</p>",
        "<table><tr><th class=l>joint</th><th>peak</th><th>worst peak</th><th>rms</th><th>worst rms</th>"
        "<th>adjusted peak</th><th>adjusted rms</th></tr>",
    ]
    for row in analysis.joints:
        cells = "".join(
            f"<td>{row[key]:.4g}</td>"
            for key in ("peak", "worst_peak", "rms", "worst_rms", "adjusted_peak", "adjusted_rms")
        )
        parts.append(f"<tr><td class=l>{e(row['joint'])} [{e(row['unit'])}]</td>{cells}</tr>")
    parts.append("</table>")
    parts.append("<table><tr>" + "".join(f"<th class=l>{e(cell)}</th>" for cell in _SPRING_HEAD) + "</tr>")
    for line in _spring_rows(analysis):
        parts.append("<tr>" + "".join(f"<td class=l>{e(cell)}</td>" for cell in line) + "</tr>")
    parts.append("</table>")
    if analysis.corners:
        parts.append(f"<p>{e(_corner_lines(analysis)[0].strip())}</p>")
        parts.append(
            "<table><tr>" + "".join(f"<th class=l>{e(cell)}</th>" for cell in _corner_head(analysis)) + "</tr>"
        )
        for line in _corner_rows(analysis):
            parts.append("<tr>" + "".join(f"<td class=l>{e(cell)}</td>" for cell in line) + "</tr>")
        parts.append("</table>")
    return parts
