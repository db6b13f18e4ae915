"""The report's plots beyond the torque sweep and histogram: written next to ``report.html`` and shown in order.

- ``spread.png``/``.svg``: each joint's torque at every workspace sample against its own angle, before and
  after, with the binned spread (:func:`springbalance.results.spread_plots.plot_residual_spread`);
- ``coils.png``/``.svg``: each coil's force against its length, its working range and the forces at its
  allowable stresses (:func:`springbalance.results.coil_plots.plot_coils`; only with coils);
- ``tolerance.png``/``.svg``: the residual's band over the springs' tolerance box around the nominal
  (:func:`springbalance.results.spread_plots.plot_tolerance_band`; only when a spring has a box).
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import NamedTuple, Sequence

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.results.coil_plots import plot_coils
from springbalance.results.plots import save_figure
from springbalance.results.spread_plots import plot_residual_spread, plot_tolerance_band


class Plot(NamedTuple):
    """One plot of the report: its SVG file (relative to the report), what it shows, and its image's alt text."""

    file: str
    caption: str
    alt: str


#: the report's plots: (file stem, the function that draws it or returns None when it does not apply, caption,
#: alt text)
PLOTS = (
    (
        "spread",
        plot_residual_spread,
        "Torque of each joint at every workspace sample against that joint's own angle, gravity only and "
        "with the springs; the bands span the least to the largest torque of the samples in each bin of the "
        "angle (the spread the other joints add).",
        "torque of each joint over the workspace against its angle, before and after",
    ),
    (
        "coils",
        plot_coils,
        "Each coil's force against its length (its spec sheet's law), the working range over the "
        "workspace (shortest to longest length) with the force at each sample, and the forces at which "
        "the body's (and the hooks') stress reaches the allowable.",
        "force against length of each coil, with its working range and allowable force",
    ),
    (
        "tolerance",
        plot_tolerance_band,
        "The nominal residual of each joint at every sample, and the band that every build within the "
        "springs' tolerance box stays in (exact over the box's corners), binned by the joint's angle.",
        "band of the residual over the tolerance box around the nominal",
    ),
)


def write_plots(result: EvaluatedDesign, folder: str | Path) -> list[Plot]:
    """Write the plots of :data:`PLOTS` that apply to ``result`` into ``folder`` (PNG and SVG); returns them."""
    folder = Path(folder)
    plots = []
    for stem, draw, caption, alt in PLOTS:
        figure = draw(result)
        if figure is not None:
            save_figure(figure, folder / f"{stem}.png")
            plots.append(Plot(f"{stem}.svg", caption, alt))
    return plots


def plots_html(plots: Sequence[Plot]) -> list[str]:
    """The plots as paragraphs of the report (a caption, then the image)."""
    e = html.escape
    return [f'<p>{e(plot.caption)}</p><p><img src="{e(plot.file)}" alt="{e(plot.alt)}"></p>' for plot in plots]
