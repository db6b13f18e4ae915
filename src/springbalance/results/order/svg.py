"""The primitives of a technical drawing in SVG, in millimetres of the sheet: lines of the ISO 128 widths,
text, dimensions with arrowheads and extension lines (ISO 129), leaders, and tables.

Every function returns SVG element text; :class:`Canvas` collects them. Coordinates are sheet millimetres,
``x`` to the right and ``y`` down (SVG's); a caller that draws a part converts its model coordinates.
"""

from __future__ import annotations

import math
from typing import Sequence
from xml.sax.saxutils import escape

#: line widths [mm] (ISO 128: visible outlines 0.5, thin lines 0.25, fine 0.18)
THICK, THIN, FINE = 0.5, 0.25, 0.18
#: text height [mm] of dimensions and table entries, and of titles
TEXT, TITLE = 2.5, 3.5
#: arrowhead length [mm]
ARROW = 2.5


def _f(value: float) -> str:
    return f"{value:.3f}".rstrip("0").rstrip(".")


class Canvas:
    """A list of SVG elements, in sheet millimetres."""

    def __init__(self) -> None:
        self.elements: list[str] = []

    def add(self, element: str) -> None:
        self.elements.append(element)

    def clip(self, x: float, y: float, w: float, h: float) -> None:
        """Draw what follows (until :meth:`unclip`) inside the rectangle only (a ground end cuts the coil)."""
        name = f"clip{len(self.elements)}"
        self.add(
            f'<clipPath id="{name}"><rect x="{_f(x)}" y="{_f(y)}" width="{_f(w)}" height="{_f(h)}"/></clipPath>'
            f'<g clip-path="url(#{name})">'
        )

    def unclip(self) -> None:
        self.add("</g>")

    def line(self, x1: float, y1: float, x2: float, y2: float, width: float = THIN, dash: str = "") -> None:
        """A straight line; ``dash``: an SVG dash array ("" solid)."""
        style = f' stroke-dasharray="{dash}"' if dash else ""
        self.add(
            f'<line x1="{_f(x1)}" y1="{_f(y1)}" x2="{_f(x2)}" y2="{_f(y2)}" stroke="black" '
            f'stroke-width="{_f(width)}"{style}/>'
        )

    def centre_line(self, x1: float, y1: float, x2: float, y2: float) -> None:
        """A thin chain line (long dash, dot): an axis."""
        self.line(x1, y1, x2, y2, FINE, "8 1.5 1 1.5")

    def polygon(self, points: Sequence[tuple[float, float]], fill: str = "white", width: float = THIN) -> None:
        text = " ".join(f"{_f(x)},{_f(y)}" for x, y in points)
        self.add(f'<polygon points="{text}" fill="{fill}" stroke="black" stroke-width="{_f(width)}"/>')

    def ring(self, cx: float, cy: float, inner: float, outer: float, width: float = THIN) -> None:
        """An annulus (a loop of wire seen face-on): radii ``inner`` and ``outer`` [mm]."""
        path = " ".join(
            f"M {_f(cx + r)} {_f(cy)} A {_f(r)} {_f(r)} 0 1 0 {_f(cx - r)} {_f(cy)} A {_f(r)} {_f(r)} 0 1 0 "
            f"{_f(cx + r)} {_f(cy)} Z"
            for r in (outer, inner)
        )
        self.add(f'<path d="{path}" fill="white" fill-rule="evenodd" stroke="black" stroke-width="{_f(width)}"/>')

    def rect(self, x: float, y: float, w: float, h: float, width: float = THIN, fill: str = "none") -> None:
        self.add(
            f'<rect x="{_f(x)}" y="{_f(y)}" width="{_f(w)}" height="{_f(h)}" fill="{fill}" stroke="black" '
            f'stroke-width="{_f(width)}"/>'
        )

    def text(
        self,
        x: float,
        y: float,
        content: str,
        size: float = TEXT,
        anchor: str = "start",
        rotate: float = 0.0,
        bold: bool = False,
        css: str = "",
    ) -> None:
        """Text whose baseline starts (``anchor``: start, middle, end) at ``(x, y)``; ``rotate`` [deg]."""
        turn = f' transform="rotate({_f(rotate)} {_f(x)} {_f(y)})"' if rotate else ""
        weight = ' font-weight="bold"' if bold else ""
        cls = f' class="{css}"' if css else ""
        self.add(
            f'<text x="{_f(x)}" y="{_f(y)}" font-size="{_f(size)}" text-anchor="{anchor}"{weight}{turn}{cls}>'
            f"{escape(content)}</text>"
        )

    def arrow(self, x: float, y: float, angle: float) -> None:
        """A filled arrowhead with its tip at ``(x, y)`` pointing along ``angle`` [rad]."""
        back, half = ARROW, ARROW / 6
        c, s = math.cos(angle), math.sin(angle)
        points = [
            (x, y),
            (x - back * c - half * s, y - back * s + half * c),
            (x - back * c + half * s, y - back * s - half * c),
        ]
        self.polygon(points, fill="black", width=FINE)

    def dimension(
        self,
        start: tuple[float, float],
        end: tuple[float, float],
        offset: float,
        label: str,
        css: str = "dimension",
    ) -> None:
        """A dimension between the feature points ``start`` and ``end``: extension lines from them, the
        dimension line ``offset`` [mm] away (to the left of the direction start → end: up for a horizontal
        one drawn left to right), arrowheads inside, ``label`` above the line's middle."""
        (x1, y1), (x2, y2) = start, end
        length = math.hypot(x2 - x1, y2 - y1)
        ux, uy = (x2 - x1) / length, (y2 - y1) / length
        nx, ny = uy, -ux  # the left normal (sheet y down)
        a = (x1 + nx * offset, y1 + ny * offset)
        b = (x2 + nx * offset, y2 + ny * offset)
        gap, over = 1.0, 1.5
        sign = 1.0 if offset >= 0 else -1.0
        for (px, py), (qx, qy) in ((start, a), (end, b)):
            self.line(px + nx * gap * sign, py + ny * gap * sign, qx + nx * over * sign, qy + ny * over * sign, FINE)
        self.line(*a, *b, FINE)
        angle = math.atan2(uy, ux)
        self.arrow(*b, angle)
        self.arrow(*a, angle + math.pi)
        mx, my = (a[0] + b[0]) / 2 + nx * 1.0 * sign, (a[1] + b[1]) / 2 + ny * 1.0 * sign
        rotation = math.degrees(angle)
        if rotation > 90 or rotation <= -90:
            rotation -= 180 if rotation > 0 else -180
        self.text(mx, my, label, anchor="middle", rotate=rotation, css=css)

    def leader(self, tip: tuple[float, float], knee: tuple[float, float], label: str, css: str = "leader") -> None:
        """A leader from the feature at ``tip`` to ``knee``, a short shoulder and ``label`` on it."""
        self.line(*knee, *tip, FINE)
        self.arrow(*tip, math.atan2(tip[1] - knee[1], tip[0] - knee[0]))
        right = knee[0] >= tip[0]
        end = knee[0] + (4 if right else -4)
        self.line(*knee, end, knee[1], FINE)
        self.text(end + (1 if right else -1), knee[1] + 0.9, label, anchor="start" if right else "end", css=css)

    def table(
        self, x: float, y: float, widths: Sequence[float], rows: Sequence[Sequence[str]], row_height: float = 5.0
    ) -> float:
        """A table of ``rows`` (the first one its header, bold) with column ``widths`` [mm], top left at
        ``(x, y)``; returns its bottom [mm]."""
        total = sum(widths)
        self.rect(x, y, total, row_height * len(rows), THIN)
        for index, row in enumerate(rows):
            top = y + index * row_height
            if index:
                self.line(x, top, x + total, top, FINE)
            left = x
            for width, cell in zip(widths, row):
                self.text(left + 1.2, top + row_height - 1.5, cell, bold=index == 0)
                left += width
        left = x
        for width in widths[:-1]:
            left += width
            self.line(left, y, left, y + row_height * len(rows), FINE)
        return y + row_height * len(rows)

    def svg(self, width: float, height: float, title: str) -> str:
        """The document: ``width`` × ``height`` mm, white, with ``title``."""
        body = "\n".join(self.elements)
        return (
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{_f(width)}mm" height="{_f(height)}mm" '
            f'viewBox="0 0 {_f(width)} {_f(height)}" font-family="DejaVu Sans, Arial, Helvetica, sans-serif">\n'
            f"<title>{escape(title)}</title>\n"
            f'<rect x="0" y="0" width="{_f(width)}" height="{_f(height)}" fill="white"/>\n{body}\n</svg>\n'
        )
