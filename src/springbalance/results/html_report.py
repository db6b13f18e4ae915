"""The HTML report of a design: one folder with ``report.html`` and what it shows.

``write_report(result, "out/")`` writes

- ``out/report.html``: the design table (per spring: anchors, stiffness, free length,
  preload, shortest and longest length, largest force over the workspace), the metrics
  table (per joint peak and RMS before/after with the reduction, every objective before
  and after), the warnings (:mod:`springbalance.results.flags`), the plots and a link to the scene;
- ``out/scene.html``: the self-contained Meshcat scene (:func:`springbalance.viz.scene.scene_html`);
- ``out/torques.png`` / ``.svg``: torque along a sweep of each joint (:func:`springbalance.results.plots.plot_torques`);
- ``out/histogram.png`` / ``.svg``: torque over the workspace samples (:func:`springbalance.results.plots.plot_histogram`);
- ``out/spread``, ``coils`` and ``tolerance`` ``.png`` / ``.svg``: each joint's torque against its own angle over the
  workspace with its spread, the coils' force against length, the residual's band over the tolerance box
  (:mod:`springbalance.results.report_plots`; the last two only when they apply).

Every number is read from the design (:class:`~springbalance.design.evaluated.EvaluatedDesign`); the page needs
no network (the images are files next to it).
"""

from __future__ import annotations

import datetime
import html
import math
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from springbalance._version import __version__
from springbalance.design.evaluated import EvaluatedDesign
from springbalance.files import write_text_atomic
from springbalance.results import plots, report_plots
from springbalance.results.clearance import checked_clearance
from springbalance.results.flags import Flag, flags
from springbalance.results.own_link import inside_own_link
from springbalance.results.pseudo_base_report import pseudo_base_html
from springbalance.results.report import balance_statement, spec_sheet_rows, spring_mass_statement
from springbalance.results.tolerance_report import tolerance_html
from springbalance.results.verification_report import verification_html
from springbalance.viz.design_scene import DesignScene


def _number(value: float | None, digits: int = 4) -> str:
    if value is None:
        return "—"
    value = float(value)
    if not math.isfinite(value):
        return "—"
    return f"{value:.{digits}g}"


def _point(point: Sequence[float]) -> str:
    return "(" + ", ".join(f"{v:+.4f}" for v in point) + ")"


#: parameter shown in the "preload" column, by spring parameter name (the first one present)
PRELOAD_KEYS = ("initial_tension", "preload", "force")


def spec_sheet_html(result: EvaluatedDesign) -> list[str]:
    """The "Spec sheets" section: per helical coil spring its data sheet and buildable verdict."""
    e = html.escape
    sheets = [(record["name"], record["helical"]) for record in result.springs if "helical" in record]
    if not sheets:
        return []
    parts = [
        '<h2 id="spec-sheets">Spec sheets</h2>',
        '<p class="note">Each helical spring as a part to order or wind (Shigley, ch. 10); the verdict names '
        "every rule it fails.</p>",
    ]
    for name, sheet in sheets:
        verdict = (
            "<b>buildable</b>"
            if sheet["buildable"]
            else "<b>not buildable</b>: " + "; ".join(e(reason) for reason in sheet["reasons"])
        )
        parts.append(f"<h3>{e(name)}: {e(sheet['type'])} spring, {verdict}</h3>")
        parts.append(
            "<table>"
            + "".join(
                f"<tr><td class=l>{e(label)}</td><td>{e(value)}</td></tr>" for label, value in spec_sheet_rows(sheet)
            )
            + "</table>"
        )
    return parts


def design_rows(result: EvaluatedDesign) -> list[dict[str, Any]]:
    """Per spring: the numbers of the design table, with their units.

    ``where`` says where the spring acts (its anchors, or its joint); ``stiffness``,
    ``free_length`` and ``preload`` (initial tension, preload or constant force) are None
    when the law has no such parameter; ``min_state``/``max_state`` are the shortest and
    longest length [m] (joint angle [rad] of a torsional spring) over the workspace, and
    ``max_force`` the largest force magnitude [N] (torque [N·m]).
    """
    evaluation = result.evaluation
    rows = []
    for column, (record, spring) in enumerate(zip(result.springs, result.problem.springs)):
        states, forces = evaluation.lengths[:, column], evaluation.tensions[:, column]
        units = dict(getattr(spring, "parameter_units", {}))
        preload_key = next((key for key in PRELOAD_KEYS if key in units), None)
        if "a" in record and "b" in record:
            where = [(end, record[end]["body"], record[end]["point"]) for end in spring.anchors]
        else:
            where = [("joint", record.get("joint", "?"), None)]
        state_unit = getattr(spring, "state_quantity", ("length", "m"))
        force_unit = getattr(spring, "force_quantity", ("tension", "N"))
        rows.append(
            {
                "name": record["name"],
                "type": record["type"],
                "where": where,
                "stiffness": record.get("stiffness"),
                "stiffness_unit": units.get("stiffness", ""),
                "free_length": record.get("free_length"),
                "preload": record.get(preload_key) if preload_key else None,
                "preload_unit": units.get(preload_key, "") if preload_key else "",
                "preload_name": preload_key or "",
                "min_state": float(states.min()),
                "max_state": float(states.max()),
                "state": state_unit,
                "max_force": float(np.max(np.abs(forces))),
                "force": force_unit,
                "mass": record.get("mass"),
            }
        )
    return rows


def _where(row: dict[str, Any]) -> str:
    parts = []
    for end, body, point in row["where"]:
        if point is None:
            parts.append(f"joint {html.escape(str(body))}")
        else:
            parts.append(f"{end}: {html.escape(str(body))} {_point(point)}")
    return "<br>".join(parts)


def _with_unit(value: float | None, unit: str, default_unit: str, digits: int = 5) -> str:
    text = _number(value, digits)
    return text if value is None or unit == default_unit else f"{text} {html.escape(unit)}"


def report_html(
    result: EvaluatedDesign,
    scene: str | None = "scene.html",
    torques: str | None = "torques.svg",
    histogram: str | None = "histogram.svg",
    legend: str = "",
    exports: Iterable[str] = (),
    figures: Sequence[report_plots.Plot] = (),
) -> str:
    """The report page; ``scene``, ``torques`` and ``histogram`` are relative links (None: left out);
    ``exports``: relative links to exported URDF/MJCF files (``springbalance export``); ``figures``: the further
    plots (:func:`springbalance.results.report_plots.write_plots`), shown after the torque plots.

    The sections, in order: the head (:func:`head_html`), the links (:func:`links_html`), the springs
    (:func:`springs_html`, :func:`spec_sheet_html`), the springs' mass, the pseudo-bases
    (:func:`~springbalance.results.pseudo_base_report.pseudo_base_html`, when the design has any), the torque and objective tables (:func:`torque_html`),
    the balance statement, the scenarios (:func:`scenarios_html`), the infeasibility, the clearance
    (:func:`clearance_html`), the verification (:func:`~springbalance.results.verification_report.verification_html`),
    the failures and warnings (:func:`warnings_html`) and the plots (:func:`plots_html`).
    """
    metrics = result.metrics()
    e = html.escape
    parts = head_html(result)
    parts.extend(links_html(scene, legend, exports))
    parts.extend(springs_html(result))
    parts.extend(spec_sheet_html(result))
    first, second = spring_mass_statement(result.spring_mass())
    parts.append(f'<p id="spring-mass">{e(first[0].upper() + first[1:])}: {e(second)}.</p>')
    parts.extend(pseudo_base_html(result))
    parts.extend(torque_html(metrics))
    parts.append(f"<p>{e(balance_statement(result))}.</p>")
    if getattr(result.problem, "scenarios", None):
        parts.extend(scenarios_html(result))
    if metrics["max_violation"] > 1e-6:
        parts.append(f"<p><b>Infeasible:</b> largest constraint violation {_number(metrics['max_violation'])}.</p>")
    parts.extend(clearance_html(result))
    parts.extend(verification_html(result))
    parts.extend(tolerance_html(result))
    parts.extend(warnings_html(flags(result)))
    parts.extend(plots_html(torques, histogram))
    parts.extend(report_plots.plots_html(figures))
    parts.append("</body></html>")
    return "\n".join(parts)


def head_html(result: EvaluatedDesign) -> list[str]:
    """The page's head (title, style) and its first lines: the mechanism, the workspace samples, the
    objective, the solver's status and method, the version of springbalance and today's date."""
    problem = result.problem
    e = html.escape
    return [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>springbalance report: {e(problem.mechanism.name)}</title>",
        "<style>body{font:14px/1.45 sans-serif;margin:24px auto;max-width:1100px;color:#222;padding:0 16px}"
        "table{border-collapse:collapse;margin:8px 0 20px}th,td{border:1px solid #ccc;padding:3px 8px;"
        "text-align:right}th{background:#f2f2f2}td.l,th.l{text-align:left}img{max-width:100%}"
        ".note{color:#555;font-size:13px}code{background:#f4f4f4;padding:0 3px}</style></head><body>",
        f"<h1>Spring design for {e(problem.mechanism.name)}</h1>",
        f'<p class="note">{problem.workspace.size} workspace samples ({e(str(problem.workspace.description.get("kind")))}), '
        f"objective <code>{e(problem.objective.name)}</code>, solver status <code>{e(str(result.status))}</code>, "
        f"method <code>{e(str(result.method))}</code>. springbalance {e(__version__)}, "
        f"{datetime.date.today().isoformat()}.{_seeds_note(result)}</p>",
    ]


def _seeds_note(result: EvaluatedDesign) -> str:
    """The head's sentence on a design solved at several seeds (empty for one seed)."""
    search = getattr(result, "seed_search", None)  # a DesignResult's (results.seed_search.SeedSearch)
    return "" if search is None else " " + html.escape(search.summary(result.problem.objective.unit))


def links_html(scene: str | None, legend: str, exports: Iterable[str]) -> list[str]:
    """The link to the 3-D scene (with its colour ``legend``) and to the exported models (relative links)."""
    e = html.escape
    parts = []
    if scene:
        parts.append(
            f'<p><a href="{e(scene)}"><b>Open the 3-D scene</b></a> (Meshcat: the arm and its springs, '
            "animated through a sweep of each joint; opens offline).</p>"
        )
        if legend:
            parts.append(f'<div style="position:relative;height:64px">{legend}</div>')
    if exports:
        links = ", ".join(f'<a href="{e(name)}"><code>{e(name)}</code></a>' for name in exports)
        parts.append(f"<p>Exported models (URDF with spring anchors, MuJoCo model with tendon springs): {links}.</p>")
    return parts


def springs_html(result: EvaluatedDesign) -> list[str]:
    """The "Springs" section: the table of :func:`design_rows` (anchors [m], stiffness [N/m], free length [m],
    preload [N], shortest and longest length [m], largest force [N])."""
    e = html.escape
    parts = [
        "<h2>Springs</h2>",
        '<p class="note">Anchor points in the frame of their body [m]. Lengths and forces over the '
        "workspace samples; max force is the largest magnitude (tension pulls the ends together, "
        "a compression or gas spring pushes). A torsional spring gives its joint, angles [rad] and "
        "torques [N·m].</p>",
        "<table><tr><th class=l>spring</th><th class=l>type</th><th class=l>anchors (body, point [m])</th>"
        "<th>stiffness [N/m]</th><th>free length [m]</th><th>preload [N]</th><th>min length [m]</th>"
        "<th>max length [m]</th><th>max force [N]</th></tr>",
    ]
    for row in design_rows(result):
        state_unit, force_unit = row["state"][1], row["force"][1]
        preload = _with_unit(row["preload"], row["preload_unit"], "N")
        if row["preload_name"] and row["preload_name"] != "initial_tension" and row["preload"] is not None:
            preload += f" ({e(row['preload_name'].replace('_', ' '))})"
        parts.append(
            f"<tr><td class=l>{e(row['name'])}</td><td class=l>{e(row['type'])}</td><td class=l>{_where(row)}</td>"
            f"<td>{_with_unit(row['stiffness'], row['stiffness_unit'], 'N/m', 6)}</td>"
            f"<td>{_number(row['free_length'], 5)}</td><td>{preload}</td>"
            f"<td>{_with_unit(row['min_state'], state_unit, 'm', 4)}</td>"
            f"<td>{_with_unit(row['max_state'], state_unit, 'm', 4)}</td>"
            f"<td>{_with_unit(row['max_force'], force_unit, 'N', 4)}</td></tr>"
        )
    parts.append("</table>")
    return parts


def torque_html(metrics: dict[str, Any]) -> list[str]:
    """The "Actuator torque" section: the tables of
    :meth:`~springbalance.design.evaluated.EvaluatedDesign.metrics` (per joint peak and RMS torque [N·m or N]
    before/after with the reduction [%], every objective before/after)."""
    e = html.escape
    parts = [
        "<h2>Actuator torque</h2>",
        "<table><tr><th class=l>joint</th><th>peak before</th><th>peak after</th><th>reduction [%]</th>"
        "<th>RMS before</th><th>RMS after</th><th>reduction [%]</th></tr>",
    ]
    for row in metrics["joints"]:
        parts.append(
            f"<tr><td class=l>{e(row['joint'])} [{e(row['unit'])}]</td><td>{_number(row['peak_before'])}</td>"
            f"<td>{_number(row['peak_after'])}</td><td>{_number(row['peak_reduction_percent'], 3)}</td>"
            f"<td>{_number(row['rms_before'])}</td><td>{_number(row['rms_after'])}</td>"
            f"<td>{_number(row['rms_reduction_percent'], 3)}</td></tr>"
        )
    parts.append("</table>")
    parts.append(
        "<table><tr><th class=l>objective</th><th>before</th><th>after</th><th>reduction [%]</th><th class=l></th></tr>"
    )
    for name, row in metrics["objectives"].items():
        mark = "optimised" if name == metrics["optimised"] else ""
        if not math.isfinite(row["before"]):
            mark = "needs an ordered workspace"
        parts.append(
            f"<tr><td class=l>{e(name)} [{e(row['unit'])}]</td><td>{_number(row['before'])}</td>"
            f"<td>{_number(row['after'])}</td><td>{_number(row['reduction_percent'], 3)}</td>"
            f"<td class=l>{e(mark)}</td></tr>"
        )
    parts.append("</table>")
    return parts


def scenarios_html(result: EvaluatedDesign) -> list[str]:
    """The "Scenarios" section: per load case its payload [kg], per-scenario variables, peak and RMS
    residual [N·m]."""
    problem = result.problem
    e = html.escape
    rows = problem.scenario_table(result.x)
    names = list(rows[0]["variables"]) if rows else []
    parts = [
        f"<h2>Scenarios</h2><p>{len(rows)} load cases, objective aggregated as "
        f"{e(problem.aggregate)}; the tables above cover every scenario's samples.</p>",
        "<table><tr><th class=l>scenario</th><th>payload [kg]</th>"
        + "".join(f"<th>{e(name)}</th>" for name in names)
        + "<th>peak [N·m]</th><th>rms [N·m]</th></tr>",
    ]
    for row in rows:
        parts.append(
            f"<tr><td class=l>{e(row['name'])}</td><td>{_number(row['payload'])}</td>"
            + "".join(f"<td>{_number(row['variables'][name], 6)}</td>" for name in names)
            + f"<td>{_number(row['peak'])}</td><td>{_number(row['rms'])}</td></tr>"
        )
    parts.append("</table>")
    return parts


def plots_html(torques: str | None, histogram: str | None) -> list[str]:
    """The "Plots" section: the torque sweep and histogram images (relative links; None: left out)."""
    e = html.escape
    parts = []
    if torques or histogram:
        parts.append("<h2>Plots</h2>")
    if torques:
        parts.append(
            f"<p>Torque of each joint along a sweep of that joint, the others at the middle of their "
            f'workspace ranges.</p><p><img src="{e(torques)}" alt="torque along a sweep of each joint"></p>'
        )
    if histogram:
        parts.append(
            f"<p>Torque of each joint over all workspace samples.</p>"
            f'<p><img src="{e(histogram)}" alt="histogram of the torques over the workspace"></p>'
        )
    return parts


def clearance_html(result: EvaluatedDesign) -> list[str]:
    """The "Clearance" section: per spring its smallest distance to a link of the arm's collision
    geometry, the link and the pose (nothing when the URDF has no collision geometry)."""
    report = checked_clearance(result)
    if report is None:
        return []
    e = html.escape
    parts = [
        '<h2 id="clearance">Clearance</h2>',
        f'<p class="note">{e(report.lines()[0])}.</p>',
        "<table><tr><th class=l>spring</th><th>radius [mm]</th><th>clearance [mm]</th>"
        "<th class=l>closest link</th><th class=l>status</th><th class=l>at pose</th></tr>",
    ]
    for row in report.rows:
        spring, radius, distance, link, status, pose = (e(cell) for cell in report.cells(row))
        parts.append(
            f"<tr><td class=l>{spring}</td><td>{radius}</td><td>{distance}</td><td class=l>{link}</td>"
            f"<td class=l>{status.lower()}</td><td class=l>{pose}</td></tr>"
        )
    parts.append("</table>")
    return parts


def warnings_html(flags: Sequence[Flag]) -> list[str]:
    """The findings: a "Failures" section first when there are failures (rows of class ``failure <kind>``),
    then the "Warnings" section (rows of class ``warning <kind>``): tables of kind, subject, message and
    hint, or "Warnings: none"."""
    failed = [flag for flag in flags if flag.failure]
    warned = [flag for flag in flags if not flag.failure]
    parts: list[str] = []
    if failed:
        parts.append('<h2 id="failures">Failures</h2>')
        parts.append(f"<p><b>This design does not pass:</b> {len(failed)} failure(s).</p>")
        parts.extend(_flag_table(failed, "failure"))
    parts.append('<h2 id="warnings">Warnings</h2>')
    if not warned:
        return parts + ["<p>Warnings: none.</p>"]
    return parts + _flag_table(warned, "warning")


def _flag_table(flags: Sequence[Flag], severity: str) -> list[str]:
    e = html.escape
    parts = [
        "<table><tr><th class=l>kind</th><th class=l>subject</th><th class=l>finding</th><th class=l>hint</th></tr>"
    ]
    for flag in flags:
        parts.append(
            f'<tr class="{severity} {e(flag.kind)}"><td class=l><code>{e(flag.kind)}</code></td>'
            f"<td class=l>{e(flag.subject)}</td><td class=l>{e(flag.message)}</td>"
            f"<td class=l>{e(flag.hint or '')}</td></tr>"
        )
    parts.append("</table>")
    return parts


def exported_files(folder: str | Path) -> list[str]:
    """Names of the URDF (``*.urdf``) and MuJoCo (``*.xml`` with a ``<mujoco>`` root) files in ``folder``."""
    names = []
    for path in sorted(Path(folder).glob("*")):
        if path.suffix == ".urdf":
            names.append(path.name)
        elif path.suffix == ".xml":
            with open(path, "rb") as stream:
                if b"<mujoco" in stream.read(512):
                    names.append(path.name)
    return names


def write_report(result: EvaluatedDesign, folder: str | Path, scene: bool = True, **scene_options: Any) -> Path:
    """Write ``report.html``, ``scene.html`` and the plots (PNG and SVG) into ``folder``.

    Returns the path of ``report.html``. ``scene=False`` leaves the scene out;
    ``scene_options`` go to :class:`springbalance.viz.scene.DesignScene`. A spring that runs inside its
    own link beyond its anchor (:func:`~springbalance.results.own_link.inside_own_link`) is drawn red
    in the scene and named in its legend.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    plots.plot_torques(result, path=folder / "torques.png")
    plots.plot_histogram(result, path=folder / "histogram.png")
    figures = report_plots.write_plots(result, folder)
    legend = ""
    if scene:
        inside = {
            f.spring: f"runs inside {f.body} beyond its anchor ({1e3 * f.depth:.3g} mm)"
            for f in inside_own_link(result)
        }
        design_scene = DesignScene(result, **{"flagged": inside, **scene_options})
        write_text_atomic(folder / "scene.html", design_scene.html())
        legend = design_scene.legend_html(position="absolute")
    page = report_html(
        result, scene="scene.html" if scene else None, legend=legend, exports=exported_files(folder), figures=figures
    )
    return write_text_atomic(folder / "report.html", page)
