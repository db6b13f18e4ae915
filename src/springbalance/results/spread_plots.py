"""Plots of the residual over the whole workspace: each joint's torque against its own pose, with its spread.

- :func:`plot_residual_spread`: per moving joint, every workspace sample's torque of that joint against
  that joint's own angle, gravity only ("before") and with the springs ("after"), as points and as a
  band: in each of ``bins`` equal bins of the angle, from the least to the largest torque of its
  samples (the other joints vary within the workspace: the band's width is what they add).
- :func:`plot_tolerance_band`: per joint, the nominal residual and the band that the springs' tolerance
  box spans (:mod:`springbalance.design.tolerance`: at each sample the least and largest residual over
  every build, exact over the box's corners), binned the same way.

Axes: revolute and continuous joint angles in degrees, prismatic positions in m; torques in N·m (N).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.robust import nominal_design
from springbalance.design.tolerance import analyse_tolerance
from springbalance.model import sweeps
from springbalance.model.mechanism import Joint
from springbalance.results.plots import (
    AFTER_COLOR,
    BEFORE_COLOR,
    flat_if_none,
    largest_torque,
    new_figure,
    save_figure,
    say_if_unchanged,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: bins of a joint's range in the bands
BINS = 16
TOLERANCE_COLOR = "#2b8cbe"


def binned_band(x: np.ndarray, low: np.ndarray, high: np.ndarray, bins: int = BINS) -> tuple[np.ndarray, ...]:
    """The band of ``low``…``high`` over ``x`` as steps: split ``[min x, max x]`` into ``bins`` equal bins; each
    bin that holds a sample spans its width at the least ``low`` and the largest ``high`` of its samples.
    Returns ``(x, lower, upper)``, two points per such bin (its left and right edge)."""
    edges = np.linspace(x.min(), x.max(), bins + 1) if x.max() > x.min() else np.array([x.min() - 0.5, x.min() + 0.5])
    index = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)
    steps, lower, upper = [], [], []
    for b in range(len(edges) - 1):
        members = index == b
        if members.any():
            steps += [edges[b], edges[b + 1]]
            lower += [low[members].min()] * 2
            upper += [high[members].max()] * 2
    return np.array(steps), np.array(lower), np.array(upper)


def _angle(joint: Joint, values: np.ndarray) -> tuple[np.ndarray, str]:
    if joint.kind == "prismatic":
        return values, f"{joint.name} [m]"
    return np.rad2deg(values), f"{joint.name} [deg]"


def _panels(
    result: EvaluatedDesign, values: np.ndarray, title: str
) -> tuple[Figure, list[tuple[Joint, Axes, np.ndarray, str]]]:
    """A figure with one panel per moving joint: (joint, axes, its samples' angle in ``values`` (N×nv), the x
    label)."""
    joints = sweeps.moving_joints(result)
    columns = min(len(joints), 3) or 1
    lines = int(np.ceil(len(joints) / columns)) or 1
    figure = new_figure(figsize=(4.4 * columns, 3.3 * lines), layout="constrained")
    figure.suptitle(title, fontsize="medium")
    panels = []
    for number, joint in enumerate(joints):
        axes = figure.add_subplot(lines, columns, number + 1)
        x, label = _angle(joint, values[:, joint.index_v])
        axes.set_xlabel(label)
        axes.set_ylabel(f"{joint.name} torque [{joint.torque_unit}]")
        axes.axhline(0.0, color="black", linewidth=0.6)
        axes.grid(True, alpha=0.3)
        panels.append((joint, axes, x, label))
    if not panels:
        axes = figure.add_subplot()
        axes.text(0.5, 0.5, "the workspace holds every joint still", ha="center", va="center")
        axes.set_axis_off()
    return figure, panels


def _band(axes: Axes, x: np.ndarray, low: np.ndarray, high: np.ndarray, bins: int, gid: str, **style: Any) -> None:
    steps, lower, upper = binned_band(x, low, high, bins)
    band = axes.fill_between(steps, lower, upper, linewidth=0, **style)
    band.set_gid(gid)


def plot_residual_spread(result: EvaluatedDesign, bins: int = BINS, path: str | Path | None = None) -> Figure:
    """Each joint's torque at every workspace sample against its own angle, before and after, with the binned
    band of the spread (see the module). Artists' gids: ``before-points``/``after-points`` (the samples),
    ``before-band``/``after-band``. ``path``: also save it as PNG and SVG."""
    problem = result.problem
    before = problem.workspace.kinematics().gravity_torque
    after = result.evaluation.tau
    figure, panels = _panels(
        result,
        problem.workspace.joint_values,
        f"{problem.mechanism.name}: torque at the {problem.workspace.size} workspace samples, and its spread",
    )
    largest = largest_torque(before, after)
    for number, (joint, axes, x, _) in enumerate(panels):
        j = joint.index_v
        flat_if_none(axes, np.concatenate([before[:, j], after[:, j]]), largest)
        say_if_unchanged(axes, before[:, j], after[:, j], largest)
        _band(axes, x, before[:, j], before[:, j], bins, "before-band", color=BEFORE_COLOR, alpha=0.18)
        _band(axes, x, after[:, j], after[:, j], bins, "after-band", color=AFTER_COLOR, alpha=0.25)
        points = axes.scatter(x, before[:, j], s=7, color=BEFORE_COLOR, alpha=0.6, label="gravity only")
        points.set_gid("before-points")
        points = axes.scatter(x, after[:, j], s=7, color=AFTER_COLOR, label="with springs")
        points.set_gid("after-points")
        if number == 0:
            axes.legend(loc="best", fontsize="small")
    if path is not None:
        save_figure(figure, path)
    return figure


def plot_tolerance_band(result: EvaluatedDesign, bins: int = BINS, path: str | Path | None = None) -> Figure | None:
    """Each joint's nominal residual at every sample against its own angle, and the band the tolerance box
    spans (gid ``tolerance-band``: per bin the least lower and the largest upper envelope); None when no
    spring has a tolerance box. ``path``: also save it as PNG and SVG."""
    analysis = analyse_tolerance(result, result.tolerance)
    if not analysis.boxes:
        return None
    problem, x_nominal = nominal_design(result.problem, result.x)  # a robust design's nominal law
    tau = result.evaluation.tau if problem is result.problem else problem.evaluate(x_nominal).tau
    sources = ", ".join(sorted({box.source for box in analysis.boxes}))
    figure, panels = _panels(
        result,
        problem.workspace.joint_values,
        f"{problem.mechanism.name}: residual over the tolerance box of {len(analysis.boxes)} spring(s) ({sources})",
    )
    largest = largest_torque(analysis.lower, analysis.upper, tau)
    for number, (joint, axes, x, _) in enumerate(panels):
        j = joint.index_v
        flat_if_none(axes, np.concatenate([analysis.lower[:, j], analysis.upper[:, j], tau[:, j]]), largest)
        _band(
            axes, x, analysis.lower[:, j], analysis.upper[:, j], bins, "tolerance-band",
            color=TOLERANCE_COLOR, alpha=0.25, label="every build (worst over the box)",
        )  # fmt: skip
        points = axes.scatter(x, tau[:, j], s=7, color=AFTER_COLOR, label="nominal design")
        points.set_gid("nominal-points")
        if number == 0:
            axes.legend(loc="best", fontsize="small")
    if path is not None:
        save_figure(figure, path)
    return figure
