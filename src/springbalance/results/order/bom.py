"""The bill of materials of a design: its springs, the anchors (brackets) that hold them by body and point,
and the cables, pulleys and guides of routed springs; and the springs a maker cannot quote.

Each row is one item to buy or make: ``item`` (a number), ``category`` (``spring``, ``anchor``, ``pulley``,
``guide``, ``cable``), ``description``, ``quantity``, the ``body`` it sits on and its ``point`` in that
body's frame [mm] (anchors, pulleys, guides), the ``springs`` it serves (``name.end``), and ``notes``. Two
spring ends at the same point of the same body (within 0.1 mm) share one anchor. An anchor that stands off
its link (:mod:`springbalance.model.brackets`) notes how far, where the bracket's shortest foot is on the link
and the load it carries: the spring's largest tension ``F`` [N] over the workspace and ``F·d`` [N·m] at the
foot, ``d`` its length. :func:`bom_csv` writes the rows as CSV.
"""

from __future__ import annotations

import csv
import io
from typing import Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.model.brackets import Bracket, spring_brackets
from springbalance.results.order.form import SpringOrder

#: the columns of bom.csv
COLUMNS = ("item", "category", "description", "quantity", "body", "x_mm", "y_mm", "z_mm", "springs", "notes")
#: two anchor points closer than this [mm] (same body) are one anchor
SAME_POINT = 0.1


def not_quotable(result: EvaluatedDesign) -> list[dict[str, str]]:
    """The springs of ``result`` that are not helical coils: per spring its ``name``, ``type`` and the
    ``reason`` why a spring maker has nothing to quote for it."""
    rows = []
    for record in result.springs:
        reason = not_quotable_reason(record)
        if reason is not None:
            rows.append({"name": str(record["name"]), "type": str(record["type"]), "reason": reason})
    return rows


def not_quotable_reason(record: dict[str, Any]) -> str | None:
    """Why a spring maker cannot quote the spring of ``record`` (an ``EvaluatedDesign.springs`` entry), or
    None for a helical coil (it has a spec sheet)."""
    if "helical" in record:
        return None
    kind = str(record["type"])
    if record.get("ideal"):
        return (
            f"an ideal {kind} law (ideal: true): a rate and a free length without a coil; design it as a coil "
            "(leave ideal out) to get a part a spring maker can quote"
        )
    if kind == "gas":
        return "a gas spring: order it from a gas-spring catalogue by its force and its extended and stroke lengths"
    if kind == "torsional":
        return "a torsional law on a joint: no coil geometry; a torsion spring needs its own design (DIN 2194)"
    return f"a {kind} law without coil geometry: nothing a spring maker can quote"


def bom_rows(result: EvaluatedDesign, orders: list[SpringOrder], quantity: int = 1) -> list[dict[str, Any]]:
    """The rows of the bill of materials of ``result`` whose coils are ordered as ``orders``, ``quantity``
    of each spring (the anchors, pulleys and cables of one set per spring)."""
    by_name = {order.name: order for order in orders}
    rows: list[dict[str, Any]] = []
    anchors: dict[tuple[str, tuple[float, ...]], dict[str, Any]] = {}
    brackets = spring_brackets(result.problem.mechanism, result.springs)
    tensions = np.abs(np.asarray(result.evaluation.tensions))
    for column, record in enumerate(result.springs):
        name = str(record["name"])
        rows.append(_spring_row(record, by_name.get(name), quantity))
        force = float(np.max(tensions[:, column])) if tensions.size else 0.0
        for end in ("a", "b"):
            if end in record:
                _add_anchor(anchors, record[end], f"{name}.{end}", quantity, brackets.get((name, end)), force)
        rows.extend(_path_rows(record, quantity))
        if "joint" in record:
            rows.append(_row("anchor", f"joint mount of {name}", quantity, body=str(record["joint"]), springs=name))
    rows.extend(anchors.values())
    for item, row in enumerate(rows, start=1):
        row["item"] = item
    return rows


def _path_rows(record: dict[str, Any], quantity: int) -> list[dict[str, Any]]:
    """The pulleys, guides and cable of a routed spring's path (none for a spring between two anchors)."""
    name = str(record["name"])
    vias = [key for key in record if key.startswith("via")]
    rows = []
    for via in vias:
        radius = float(record[via].get("pulley", {}).get("radius", 0.0))
        point = [1e3 * float(value) for value in record[via]["point"]]
        what = f"pulley, radius {radius * 1e3:.4g} mm, on a swivel mount" if radius > 0 else "cable guide (eyelet)"
        rows.append(
            _row("pulley" if radius > 0 else "guide", what, quantity, record[via]["body"], point, f"{name}.{via}")
        )
    if "cable_length" in record:
        rows.append(
            _row(
                "cable",
                f"cable, {float(record['cable_length']) * 1e3:.1f} mm between its end fittings",
                quantity,
                springs=name,
                notes=f"joins {name}'s coil at {vias[0] if vias else 'b'} to its end b over its path",
            )
        )
    return rows


def _spring_row(record: dict[str, Any], order: SpringOrder | None, quantity: int) -> dict[str, Any]:
    """The row of one spring: the coil to order, or why there is none."""
    name = str(record["name"])
    if order is None:
        reason = not_quotable_reason(record) or "no spec sheet"
        return _row("spring", f"{name}: {record['type']} (not a part to order)", 0, springs=name, notes=reason)
    g = order.geometry
    material = order.field("material_grade").value
    description = (
        f"{name}: helical {order.kind} spring, {material}, d {g['wire_diameter'] * 1e3:.3g} mm, "
        f"De {(g['mean_diameter'] + g['wire_diameter']) * 1e3:.4g} mm, L0 {g['free_length'] * 1e3:.4g} mm"
    )
    return _row("spring", description, quantity, springs=name, notes=f"{order.form}: order/{name}.svg, order.html")


def _add_anchor(
    anchors: dict, end: dict[str, Any], label: str, quantity: int, held: Bracket | None, force: float
) -> None:
    """Count the anchor of a spring end ``end`` (``{body, point}``), merged with one at the same point;
    ``held``: its bracket when it stands off its link, ``force`` [N] the spring's largest tension."""
    point = [1e3 * float(value) for value in end["point"]]
    load = f"{label} pulls with up to {force:.0f} N" + (f", {force * held.length:.1f} N·m at the foot" if held else "")
    for (body, other), row in anchors.items():
        if body == end["body"] and max(abs(a - b) for a, b in zip(point, other)) < SAME_POINT:
            row["springs"] += f" {label}"
            row["description"] = row["description"].replace(
                "anchor bracket with a pin", "anchor bracket with a pin (shared)"
            )
            row["notes"] += f"; {load}" if held else ""
            return
    description, notes = "anchor bracket with a pin", ""
    if held is not None:
        foot = ", ".join(f"{1e3 * value:.1f}" for value in held.foot)
        description += f", {1e3 * held.length:.0f} mm off {held.body}"
        notes = f"a bracket to design: its shortest foot on {held.body} at ({foot}) mm; {load}"
    anchors[(str(end["body"]), tuple(point))] = _row(
        "anchor", description, quantity, str(end["body"]), point, label, notes
    )


def _row(
    category: str,
    description: str,
    quantity: int,
    body: str = "",
    point: list[float] | None = None,
    springs: str = "",
    notes: str = "",
) -> dict[str, Any]:
    x, y, z = (round(value, 2) for value in point) if point is not None else ("", "", "")
    return {
        "item": 0,
        "category": category,
        "description": description,
        "quantity": quantity,
        "body": body,
        "x_mm": x,
        "y_mm": y,
        "z_mm": z,
        "springs": springs,
        "notes": notes,
    }


def bom_csv(rows: list[dict[str, Any]]) -> str:
    """The rows as CSV text (header :data:`COLUMNS`)."""
    stream = io.StringIO()
    writer = csv.DictWriter(stream, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return stream.getvalue()
