"""The colour scale of spring forces: warm colours for tension [N], greens for compression, and the
fixed solid red of a spring that comes closer to the arm than the clearance margin.

The tension scale runs from yellow through orange to a dark raspberry (hues about 46° down to
325°). A spring below the clearance margin is drawn in :data:`CLEARANCE_RGB`, a pure red (hue 0°,
saturation and value 1) with a marker at its closest point: every colour of the scale within 14°
of its hue is at most 80 % saturated (a pinkish orange-red), every one at least 90 % saturated is
26° of hue or more away, so a census (and a reader) tells the red apart.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

#: Tension colours, from no tension to the scale's limit (RGB in [0, 1]).
TENSION_STOPS = ((0.0, (1.0, 0.85, 0.35)), (0.5, (0.96, 0.43, 0.16)), (1.0, (0.55, 0.0, 0.32)))
#: Compression colours (a spring that pushes), from none to the scale's limit.
COMPRESSION_STOPS = ((0.0, (0.75, 0.9, 0.7)), (1.0, (0.1, 0.47, 0.22)))
#: Colour of a spring in a frame where it is below the clearance margin (0xRRGGBB): pure red, full value
#: (the tension scale ends in a dark raspberry, 35° of hue away).
CLEARANCE_COLOR = 0xFF0000
#: :data:`CLEARANCE_COLOR` as RGB in [0, 1].
_RED, _GREEN, _BLUE = (((CLEARANCE_COLOR >> shift) & 0xFF) / 255.0 for shift in (16, 8, 0))
CLEARANCE_RGB = (_RED, _GREEN, _BLUE)


class ColorScale:
    """Maps a spring tension [N] to a colour: warm for tension, green for compression.

    ``limit`` [N] is the largest |tension| the scale shows; larger values saturate.
    """

    #: a pull below this fraction of the limit counts as none (solver round-off, not compression)
    slack = 1e-6

    def __init__(self, limit: float) -> None:
        self.limit = float(limit) if np.isfinite(limit) and limit > 0 else 1.0

    def pushes(self, tension: npt.ArrayLike) -> np.ndarray:
        """True where ``tension`` [N] is a real push (compression), not round-off."""
        return np.asarray(tension) < -self.slack * self.limit

    @classmethod
    def for_tensions(cls, *tensions: npt.ArrayLike) -> ColorScale:
        """The scale whose limit is the largest |tension| [N] in any of ``tensions`` (1 N when there is none)."""
        values = np.concatenate([np.abs(np.ravel(t)) for t in tensions]) if tensions else np.zeros(0)
        return cls(float(values.max()) if values.size else 1.0)

    def rgb(self, tension: float) -> tuple[float, float, float]:
        """Colour of ``tension`` [N], RGB in [0, 1]."""
        stops = TENSION_STOPS if tension >= -self.slack * self.limit else COMPRESSION_STOPS
        fraction = min(abs(float(tension)) / self.limit, 1.0)
        positions = [p for p, _ in stops]
        red, green, blue = (float(np.interp(fraction, positions, [c[i] for _, c in stops])) for i in range(3))
        return red, green, blue

    def hex(self, tension: float) -> int:
        """Colour as the 0xRRGGBB integer that meshcat materials take."""
        r, g, b = (int(round(255 * c)) for c in self.rgb(tension))
        return (r << 16) | (g << 8) | b

    def css(self, tension: float) -> str:
        return f"#{self.hex(tension):06x}"

    def describe(self) -> str:
        """One line of text for a terminal."""
        return (
            f"spring colour: tension 0 N (yellow) … {self.limit:.4g} N (dark raspberry); "
            f"compression (pushing) in greens; scale limit {self.limit:.4g} N"
        )

    def legend_html(
        self,
        compression: bool = False,
        element_id: str = "springbalance-legend",
        position: str = "fixed",
        clearance_margin: float | None = None,
        flagged: Sequence[str] = (),
    ) -> str:
        """A small HTML legend at the top left of the page (``position:fixed``) or of its container
        (``"absolute"``): the colour bar of the tension [N] with ticks, from 0 or, with ``compression``
        (some spring pushes), from ``-limit`` (negative: pushing); with ``clearance_margin`` [m] also a
        red swatch "below clearance margin (X mm)"; each line of ``flagged`` (a spring drawn red, and
        why) is listed under it."""
        low = -self.limit if compression else 0.0
        ticks = np.linspace(low, self.limit, 5 if compression else 3)
        stops = ", ".join(
            f"{self.css(value)} {100 * (value - low) / (self.limit - low):.1f}%"
            for value in np.linspace(low, self.limit, 21)
        )
        labels = "".join(
            f'<span style="position:absolute;left:{100 * (v - low) / (self.limit - low):.1f}%;'
            f'transform:translateX(-50%)">{v:.3g}</span>'
            for v in ticks
        )
        note = " (negative: pushing)" if compression else ""
        clearance = ""
        if clearance_margin is not None or flagged:
            what = "red: the springs named below, ● where each runs into a link"
            if clearance_margin is not None:
                what = f"red: below clearance margin ({1e3 * float(clearance_margin):.3g} mm), ● closest point"
            clearance = (
                f'<div class="springbalance-clearance" style="margin-top:8px;font-size:11px">'
                f'<span style="display:inline-block;width:16px;height:10px;margin-right:5px;'
                f'vertical-align:-1px;background:#{CLEARANCE_COLOR:06x}"></span>{html.escape(what)}</div>'
            )
            clearance += "".join(
                f'<div class="springbalance-flagged" style="font-size:11px;color:#c00000">{html.escape(line)}</div>'
                for line in flagged
            )
        bottom = 8 if clearance else 22
        return (
            f'<div id="{element_id}" style="position:{position};left:8px;top:8px;width:260px;'
            f"padding:6px 14px {bottom}px 14px;"
            'background:rgba(255,255,255,0.85);border-radius:4px;font:12px sans-serif;color:#222;z-index:10">'
            f"<div>spring tension [N]{html.escape(note)}</div>"
            f'<div style="height:12px;margin-top:4px;background:linear-gradient(to right, {stops})"></div>'
            f'<div style="position:relative;height:14px;margin-top:2px">{labels}</div>{clearance}</div>'
        )
