r"""The force–length plot of each helical coil: its law, where it works, and where its wire would yield.

Per coil spring of the design (a spring with a spec sheet), one panel of force [N] against length [mm]:

- **the law** (gid ``law``), from its spec sheet: an extension coil pulls :math:`F = F_i + k (L - L_0)`
  from its free length :math:`L_0` on; a compression coil pushes :math:`F = k (L_0 - L)` from its
  solid length up to :math:`L_0`;
- **the working range** (gid ``working-range``): the band from the shortest to the longest length over
  the workspace (the spec sheet's), with the force at every sample (gid ``samples``);
- **the allowable stress as a force** (gid ``allowable``): the body's shear stress is linear in the force,
  :math:`\tau = K_B\,8 F D/(\pi d^3)` (Bergsträsser), so the allowable :math:`\tau_a` is reached at
  :math:`F_a = \tau_a \pi d^3 / (8 K_B D)`; an extension coil's hooks add a line each (gids
  ``hook-bending``, ``hook-torsion``: Shigley Eq. 10-34…10-36, linear in F too);
- a compression coil's solid length (gid ``solid``).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.results.plots import AFTER_COLOR, new_figure, save_figure
from springbalance.springs.helical_formulas import hook_bending_stress, hook_torsion_stress

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

MM = 1e3  # [mm/m]


def allowable_forces(spring: Any, sheet: dict[str, Any]) -> dict[str, float]:
    """The force [N] at which each stress of ``sheet`` reaches its allowable: ``body`` (always), and for an
    extension coil ``hook bending`` and ``hook torsion``. Each stress is linear in the force."""
    d, D = sheet["wire_diameter"], sheet["mean_diameter"]
    forces = {"body": float(sheet["allowable_stress"] / spring.body_stress(1.0, sheet))}
    if "hook_bending_allowable" in sheet:
        forces["hook bending"] = float(sheet["hook_bending_allowable"] / hook_bending_stress(1.0, d, D))
    if "hook_torsion_allowable" in sheet:
        forces["hook torsion"] = float(sheet["hook_torsion_allowable"] / hook_torsion_stress(1.0, d, D))
    return forces


def law_curve(sheet: dict[str, Any], longest: float) -> tuple[np.ndarray, np.ndarray]:
    """The coil's force [N] over its lengths [m] (see the module), up to ``longest`` for an extension coil."""
    rate, free = sheet["rate"], sheet["free_length"]
    if sheet["type"] == "helical compression":
        lengths = np.linspace(sheet["solid_length"], free, 50)
        return lengths, rate * (free - lengths)
    lengths = np.linspace(free, max(longest, free * 1.01), 50)
    return lengths, sheet["initial_tension"] + rate * (lengths - free)


def _panel(axes: Axes, name: str, spring: Any, sheet: dict[str, Any], lengths: np.ndarray, forces: np.ndarray) -> None:
    shortest, longest = sheet["shortest_length"], sheet["longest_length"]
    allowable = allowable_forces(spring, sheet)
    top = max(*allowable.values(), float(np.max(np.abs(forces))))
    extension = sheet["type"] != "helical compression"
    curve_l, curve_f = law_curve(sheet, longest + 0.25 * (longest - min(shortest, sheet["free_length"])))
    (law,) = axes.plot(MM * curve_l, curve_f, color="black", linewidth=1.4, label="law (spec sheet)")
    law.set_gid("law")
    span = axes.axvspan(MM * shortest, MM * longest, color=AFTER_COLOR, alpha=0.15, label="working range")
    span.set_gid("working-range")
    points = axes.scatter(MM * lengths, np.abs(forces), s=8, color=AFTER_COLOR, zorder=3, label="workspace samples")
    points.set_gid("samples")
    styles = {"body": ("-", "#7a0177"), "hook bending": ("--", "#dd3497"), "hook torsion": (":", "#dd3497")}
    for key, force in allowable.items():
        style, color = styles[key]
        line = axes.axhline(force, linestyle=style, color=color, label=f"allowable stress, {key}: {force:.4g} N")
        line.set_gid("allowable" if key == "body" else key.replace(" ", "-"))
    if not extension:
        solid = axes.axvline(MM * sheet["solid_length"], color="grey", linestyle="--", label="solid length")
        solid.set_gid("solid")
    axes.set_ylim(0, 1.1 * top)
    axes.set_xlabel(f"{name} length [mm]")
    axes.set_ylabel("force [N]")
    axes.set_title(f"{name}: {sheet['type']}, {'buildable' if sheet['buildable'] else 'NOT buildable'}", fontsize=9)
    axes.grid(True, alpha=0.3)
    axes.legend(loc="best", fontsize=7)


def plot_coils(result: EvaluatedDesign, path: str | Path | None = None) -> Figure | None:
    """Each coil's force against its length with its working range and allowable forces (see the module); None
    when the design has no coil. ``path``: also save it as PNG and SVG."""
    coils = [
        (column, record, spring)
        for column, (record, spring) in enumerate(zip(result.springs, result.problem.springs))
        if isinstance(record.get("helical"), dict)
    ]
    if not coils:
        return None
    columns = min(len(coils), 3)
    lines = int(np.ceil(len(coils) / columns))
    figure = new_figure(figsize=(4.6 * columns, 3.6 * lines), layout="constrained")
    figure.suptitle(f"{result.problem.mechanism.name}: the coils' force against length", fontsize="medium")
    evaluation = result.evaluation
    for number, (column, record, spring) in enumerate(coils):
        axes = figure.add_subplot(lines, columns, number + 1)
        _panel(
            axes,
            record["name"],
            spring,
            record["helical"],
            evaluation.lengths[:, column],
            evaluation.tensions[:, column],
        )
    if path is not None:
        save_figure(figure, path)
    return figure
