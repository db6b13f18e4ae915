"""The dimensioned drawing of an ordered spring: an A4 sheet (SVG, millimetres) a spring maker reads.

The sheet holds the side view of the spring at a standard scale (ISO 5455: 5:1 … 1:20) with its axis, the
dimensions that are inspected (free length ``L0``, the controlled coil diameter, the wire ``d``) with their
tolerances, those for reference in parentheses (body length ``LK`` or solid length ``Lc``, the loop's inside
diameter), the table of the test states (``L0``/``F0``, ``L1``/``F1``, ``L2``/``F2`` and the rate), the
table of the order's other fields, and a title block.

The view, in the spring's own millimetres with ``x`` along the axis:

- extension spring: the loops' inner edges at ``x = 0`` and ``x = L0``, each loop a ring of inside
  diameter ``D − d`` in the plane of the sheet (loops in line), the close-wound body of length
  ``LK = d (n + 1)`` centred between them, each turn a band of width ``d`` slanted by half a pitch;
- compression spring: the ground ends at ``x = 0`` and ``x = L0``, a closed end coil at each, the active
  coils at the pitch ``p = (L0 − 2 d)/n`` (Shigley Table 10-1, squared and ground), cut flat at the ends.

A body of more than :data:`FULL_TURNS` turns is drawn simplified (ISO 2162-1): the turns at each end, and
thin chain lines through the wire's centres between them.
"""

from __future__ import annotations

import datetime
import math
from typing import Callable

from springbalance._version import __version__
from springbalance.results.order.form import SpringOrder
from springbalance.results.order.svg import FINE, THICK, TITLE, Canvas

#: model millimetres → sheet millimetres
ToSheet = Callable[[float, float], tuple[float, float]]
#: the sheet: A4 landscape [mm], its margin, and the room of the view
SHEET = (297.0, 210.0)
MARGIN = 10.0
VIEW = (35.0, 15.0, 225.0, 80.0)  # left, top, width, height [mm]
#: standard scales (ISO 5455), largest first
SCALES = (5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05)
#: bodies of more turns are drawn simplified; this many turns are drawn at each end
FULL_TURNS, END_TURNS = 24, 6


def scale_label(scale: float) -> str:
    """``2:1``, ``1:1``, ``1:5``, ..."""
    return f"{scale:g}:1" if scale >= 1 else f"1:{1 / scale:g}"


def drawing_scale(length: float, height: float) -> float:
    """The largest standard scale at which a part ``length`` × ``height`` [mm] fits the view."""
    for scale in SCALES:
        if length * scale <= VIEW[2] and height * scale <= VIEW[3]:
            return scale
    return SCALES[-1]


def _mm(value: float) -> str:
    """A length [m] in mm, to 0.01 mm."""
    return f"{value * 1e3:.2f}"


def _plus_minus(value: float | None, unit_scale: float = 1e3) -> str:
    return "" if value is None else f" ±{value * unit_scale:.3g}"


def spring_svg(order: SpringOrder, design_label: str = "") -> str:
    """The drawing of ``order`` as an SVG document (A4 landscape, millimetres)."""
    g = order.geometry
    d, D, free = g["wire_diameter"] * 1e3, g["mean_diameter"] * 1e3, g["free_length"] * 1e3
    extension = order.kind == "extension"
    length = free + 2 * d if extension else free
    scale = drawing_scale(length, D + d)
    canvas = Canvas()
    canvas.rect(MARGIN, MARGIN, SHEET[0] - 2 * MARGIN, SHEET[1] - 2 * MARGIN, THICK)
    left = VIEW[0] + (VIEW[2] - length * scale) / 2 + (d * scale if extension else 0.0)
    axis = VIEW[1] + VIEW[3] / 2 + 8.0

    def at(x: float, y: float) -> tuple[float, float]:
        return left + x * scale, axis - y * scale

    canvas.centre_line(
        *at(-0.6 * D if extension else -4 / scale, 0), *at(free + (0.6 * D if extension else 4 / scale), 0)
    )
    if extension:
        _extension_view(canvas, at, d, D, free, g["body_length"] * 1e3)
    else:
        _compression_view(canvas, at, d, D, free, g["active_coils"])
    _dimensions(canvas, at, order, scale)
    bottom = _loads_table(canvas, order)
    _fields_table(canvas, order)
    _title_block(canvas, order, scale, design_label)
    del bottom
    return canvas.svg(*SHEET, f"{order.name}: {order.form}")


def _turns(canvas: Canvas, at: ToSheet, centres: list[float], d: float, D: float, back: bool = False) -> None:
    """The body's turns: at each wire centre ``x`` the front of the turn, a band of width ``d`` from the top of
    the coil down to its bottom half a pitch on (the pitch: the distance to the next turn); with ``back``,
    the back of the turn too (a thin line up to the next turn's top). Simplified when there are many."""
    top, bottom = (D + d) / 2, -(D + d) / 2
    pitches = [after - before for before, after in zip(centres, centres[1:])]
    pitches.append(pitches[-1] if pitches else d)
    turns = list(zip(centres, pitches))
    shown = turns if len(turns) <= FULL_TURNS else turns[:END_TURNS] + turns[-END_TURNS:]
    for index, (x, pitch) in enumerate(shown):
        if back and index + 1 < len(shown) and shown[index + 1][0] - x <= pitch * 1.01:
            canvas.line(*at(x + pitch / 2, bottom), *at(x + pitch, top), FINE)
        slant = pitch / 2
        canvas.polygon(
            [at(x - d / 2, top), at(x + d / 2, top), at(x + d / 2 + slant, bottom), at(x - d / 2 + slant, bottom)]
        )
    if len(turns) > FULL_TURNS:
        start, end = centres[END_TURNS - 1] + d, centres[-END_TURNS] - d
        for y in (D / 2, -D / 2):
            canvas.centre_line(*at(start, y), *at(end, y))
        canvas.text(
            *at((start + end) / 2, D / 2 + d), f"{len(centres) - 2 * END_TURNS} turns not shown", anchor="middle"
        )


def _extension_view(canvas: Canvas, at: ToSheet, d: float, D: float, free: float, body: float) -> None:
    """Loops in line at both ends and the close-wound body between them."""
    start = (free - body) / 2
    count = max(int(round(body / d)), 1)
    centres = [start + d / 2 + i * d for i in range(count)]
    _turns(canvas, at, centres, d, D)
    scale = at(1, 0)[0] - at(0, 0)[0]
    for centre in ((D - d) / 2, free - (D - d) / 2):
        canvas.ring(*at(centre, 0), (D - d) / 2 * scale, (D + d) / 2 * scale)


def _compression_view(canvas: Canvas, at: ToSheet, d: float, D: float, free: float, active: float) -> None:
    """Closed and ground end coils and the active coils at their pitch (the back of each turn in thin
    lines), cut flat at both ends."""
    pitch = (free - 2 * d) / max(active, 1e-9)
    count = int(math.floor(active)) + 1
    centres = [d / 2] + [d + pitch * (i + 0.5) for i in range(count - 1)] + [free - d / 2]
    top, bottom = (D + d) / 2, -(D + d) / 2
    x0, y0 = at(0, top)
    x1, y1 = at(free, bottom)
    canvas.clip(x0, y0 - 1, x1 - x0, y1 - y0 + 2)
    _turns(canvas, at, centres, d, D, back=True)
    canvas.unclip()
    canvas.line(x0, y0, x0, y1, THICK)
    canvas.line(x1, y0, x1, y1, THICK)


def _dimensions(canvas: Canvas, at: ToSheet, order: SpringOrder, scale: float) -> None:
    """``L0`` above, ``LK``/``Lc`` below (reference), the controlled diameter, the wire and the loop."""
    g, tolerances = order.geometry, order.tolerances
    d, D, free = g["wire_diameter"] * 1e3, g["mean_diameter"] * 1e3, g["free_length"] * 1e3
    top = (D + d) / 2
    canvas.dimension(at(0, 0), at(free, 0), top * scale + 10, f"L0 ({_mm(g['free_length'])})")
    if order.kind == "extension":
        start = (free - g["body_length"] * 1e3) / 2
        canvas.dimension(at(start + g["body_length"] * 1e3, -top), at(start, -top), 7, f"LK ({_mm(g['body_length'])})")
        inside = (D - d) / 2
        canvas.leader(
            at(inside + inside * 0.7071, inside * 0.7071),
            at(D + 4 / scale, top + 8 / scale),
            f"loop ⌀{D - d:.2f} inside (ref.)",
        )
        wire_x = start + d / 2 + 2 * d
    else:
        wire_x = d / 2
    controlled = order.field("controlled_diameter").value == "outer (De)"
    key = "outer_diameter" if controlled else "inner_diameter"
    value = order.field(key).value
    assert isinstance(value, float)
    x_dim = free + (0.6 * D + 4 / scale if order.kind == "extension" else 4 / scale)
    half = value * 1e3 / 2
    canvas.dimension(
        at(x_dim, -half),
        at(x_dim, half),
        -6,
        f"{'De' if controlled else 'Di'} ⌀{_mm(value)}{_plus_minus(tolerances.coil_diameter)}",
    )
    wire = order.field("wire_diameter")
    canvas.leader(
        at(wire_x, -top + d * 0.3),
        at(wire_x + 10 / scale, -top - 12 / scale),
        f"d = {_mm(g['wire_diameter'])}{_plus_minus(wire.tolerance)}",
    )


def _loads_table(canvas: Canvas, order: SpringOrder) -> float:
    """The test states: length and load with its tolerance; returns the table's bottom [mm]."""
    rows = [["State", "Length L [mm]", "Load F [N]", "± F [N]"]]
    names = {"free": "0 (free)", "1": "1", "2": "2"}
    for (state, length, load), tolerance in zip(
        order.loads, (order.tolerances.initial_tension, *order.tolerances.loads)
    ):
        plus_minus = "see note" if tolerance is None else f"{tolerance:.3g}"
        if state == "free" and order.kind == "compression":
            plus_minus = "-"  # no load at the free length
        rows.append([names[state], _mm(length), f"{load:.2f}", plus_minus])
    rate = order.geometry["rate"]
    rows.append(["rate R", f"{rate / 1e3:.4g} N/mm", "(ref.)", ""])
    if order.kind == "compression":
        rows.append(["solid Lc", f"{_mm(order.geometry['solid_length'])} (ref.)", "", ""])
    return canvas.table(MARGIN + 5, 118.0, (22, 28, 24, 20), rows)


def _fields_table(canvas: Canvas, order: SpringOrder) -> None:
    """The order's other fields, two columns, next to the loads table."""

    def text(key: str) -> str:
        field = order.field(key)
        if field.value is None:
            return "see note"
        if isinstance(field.value, float):
            return f"{field.value:.4g}" + (" (ref.)" if field.reference else "")
        return field.value

    rows = [["Field", "Value"]]
    keys = ["material_standard", "material_grade", "coil_direction", "active_coils", "total_coils"]
    keys += ["loop_type", "loop_position"] if order.kind == "extension" else ["end_type", "guide"]
    keys += ["quality_grade", "cycles", "peening", "finish"]
    for key in keys:
        rows.append([order.field(key).label, text(key)[:58]])
    canvas.table(112.0, 118.0, (36, 99), rows, row_height=4.2)


def _title_block(canvas: Canvas, order: SpringOrder, scale: float, design_label: str) -> None:
    """Name, form, scale, units, the note on missing values, source, date."""
    x, y = MARGIN + 5, 183.0
    missing = [field.label for field in order.fields if field.value is None]
    notes = "Values marked 'see note' are not set by the design: see order.html for why. " if missing else ""
    notes += f"Tolerances: {order.tolerances.standard} grade {order.tolerances.grade}; (…): reference dimension."
    canvas.text(x, y - 3.5, notes, size=2.2)
    canvas.rect(x, y, SHEET[0] - 2 * MARGIN - 10, 12.0)
    canvas.text(x + 2, y + 5.5, f"{order.name}", size=TITLE, bold=True)
    canvas.text(x + 2, y + 10, f"helical {order.kind} spring, {order.form}", size=2.5)
    date = datetime.date.today().isoformat()
    canvas.text(x + 120, y + 5.5, f"Scale {scale_label(scale)}   Units: mm, N   Sheet 1/1", size=2.5)
    canvas.text(x + 120, y + 10, f"{design_label}  springbalance {__version__}  {date}", size=2.2)
