"""The verification of a design at unseen poses, as the reports show it (text and HTML).

The record is :class:`~springbalance.design.verification_record.VerificationRecord`
(:mod:`springbalance.design.verification`). The reports say "verified at N unseen poses" (or "NOT verified")
and show a short table: per rule its worst margin over the samples the design was optimised on and
over the unseen poses, and where; then per joint the residual torque's peak and RMS over both.
Margins are shown in the units a designer reads: a stress as a percentage of its full allowable,
a length in mm.
"""

from __future__ import annotations

import html
from typing import Mapping

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.verification_record import RuleMargin, VerificationRecord

#: how a margin's unit is shown: unit → (scale, shown unit)
_SHOWN = {"1": (100.0, "% of allowable"), "m": (1e3, "mm")}


def margin_text(value: float | None, unit: str) -> str:
    """A margin in the unit it is shown in (``—`` when there is none)."""
    if value is None or not np.isfinite(value):
        return "—"
    scale, shown = _SHOWN.get(unit, (1.0, unit))
    return f"{value * scale:+.3g} {shown}".rstrip()


def pose_text(pose: Mapping[str, float], joint_units: Mapping[str, str], scenario: str | None = None) -> str:
    """Joint values as text: revolute joints in degrees, prismatic ones in m (and the scenario)."""
    text = ", ".join(
        f"{name}={value:.4g} m" if joint_units.get(name) == "m" else f"{name}={np.degrees(value):.1f}°"
        for name, value in pose.items()
    )
    return f"{text} ({scenario})" if scenario is not None else text


def verdict(record: VerificationRecord) -> str:
    """One line: "verified at N unseen poses (how)" or "NOT verified …" with the rules broken, and the re-solves."""
    head = f"verified at {record.poses} unseen poses ({record.sampling})"
    if record.passed:
        text = f"{head}: every rule holds"
    else:
        broken = [rule.label for rule in record.violated]
        if not record.residual_passed:
            broken.append(f"{record.objective} residual")
        text = f"NOT {head}: {', '.join(broken)} broken"
    if record.rounds or record.mode == "resolve":
        text += f"; {record.rounds} re-solve(s), {record.added_poses} pose(s) added to the samples"
    return f"{text} ({record.seconds:.2g} s)"


def rule_cells(rule: RuleMargin, joint_units: Mapping[str, str]) -> list[str]:
    """One row of the rule table: rule, worst over the samples, worst over the unseen poses, status, where."""
    status = "ok" if rule.passed else "VIOLATED"
    return [
        rule.label,
        margin_text(rule.sampled, rule.unit),
        margin_text(rule.margin, rule.unit),
        status,
        pose_text(rule.pose, joint_units, rule.scenario),
    ]


def verification_lines(result: EvaluatedDesign) -> list[str]:
    """The "Verification" section of the text report (empty when the design was not verified)."""
    record = result.verification
    if record is None:
        return []
    units = {joint.name: joint.unit for joint in result.problem.mechanism.joints}
    table = [["rule", "worst at samples", "worst unseen", "status", "at pose"]]
    table += [rule_cells(rule, units) for rule in record.rules]
    widths = [max(len(line[column]) for line in table) for column in range(len(table[0]))]
    lines = ["Verification: " + verdict(record)]
    if record.rules:
        lines += ["  " + "  ".join(cell.ljust(w) for cell, w in zip(line, widths)).rstrip() for line in table]
    lines.append(f"  {'residual':<22s}{'peak samples':>14s}{'peak unseen':>13s}{'rms samples':>13s}{'rms unseen':>12s}")
    for row in record.residual:
        lines.append(
            f"  {row.joint + ' [' + row.unit + ']':<22s}{row.peak:14.4g}{row.dense_peak:13.4g}"
            f"{row.rms:13.4g}{row.dense_rms:12.4g}"
        )
    if record.objective_dense is not None:
        checked = " (checked)" if record.residual_checked else ""
        lines.append(
            f"  objective {record.objective}{checked}: {record.objective_sampled:.6g} at the samples, "
            f"{record.objective_dense:.6g} at the unseen poses"
        )
    return lines + [""]


def verification_html(result: EvaluatedDesign) -> list[str]:
    """The "Verification" section of ``report.html`` (nothing when the design was not verified)."""
    record = result.verification
    if record is None:
        return []
    e = html.escape
    units = {joint.name: joint.unit for joint in result.problem.mechanism.joints}
    text = verdict(record)
    parts = [
        '<h2 id="verification">Verification</h2>',
        f"<p>{e(text[0].upper() + text[1:])}.</p>",
        "<table><tr><th class=l>rule</th><th>worst at samples</th><th>worst unseen</th>"
        "<th class=l>status</th><th class=l>at pose</th></tr>",
    ]
    for rule in record.rules:
        label, sampled, margin, status, pose = (e(cell) for cell in rule_cells(rule, units))
        parts.append(
            f'<tr class="{"ok" if rule.passed else "violated"}"><td class=l>{label}</td><td>{sampled}</td>'
            f"<td>{margin}</td><td class=l>{status.lower()}</td><td class=l>{pose}</td></tr>"
        )
    parts += [
        "</table>",
        "<table><tr><th class=l>joint</th><th>peak at samples</th><th>peak unseen</th>"
        "<th>rms at samples</th><th>rms unseen</th></tr>",
    ]
    for row in record.residual:
        parts.append(
            f"<tr><td class=l>{e(row.joint)} [{e(row.unit)}]</td><td>{row.peak:.4g}</td><td>{row.dense_peak:.4g}</td>"
            f"<td>{row.rms:.4g}</td><td>{row.dense_rms:.4g}</td></tr>"
        )
    parts.append("</table>")
    return parts
