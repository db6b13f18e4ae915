"""Plots of what the actuators still carry (matplotlib, no display needed).

- :func:`plot_torques`: for each joint, its torque against its own angle along a sweep of
  that joint (the other joints at the middle of their workspace ranges,
  :func:`springbalance.model.sweeps.joint_sweep`), gravity only ("before") and with the springs
  ("after").
- :func:`plot_histogram`: the distribution of every joint's torque over all the samples of
  the design's workspace, before and after.

Figures are plain ``matplotlib.figure.Figure`` objects drawn by the Agg canvas (:func:`new_figure`),
so they work without a display and do not touch pyplot's global state; :func:`save_figure`
writes PNG and SVG. matplotlib is imported by :func:`new_figure`, on the first plot, not with this
module (importing it takes 0.2-0.4 s). Units: torques in N·m (N for prismatic joints), revolute and
continuous joint angles in degrees on the axes.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.model import sweeps
from springbalance.model.mechanism import Joint

if TYPE_CHECKING:
    from matplotlib.figure import Figure

BEFORE_COLOR = "#7f7f7f"
AFTER_COLOR = "#d7301f"
#: A joint whose torques in a plot stay within this fraction of the largest torque of any joint carries none: its
#: values are round-off (the UR5's pan, about 1e-14 N·m against the lift's 60), plotted flat on a shared scale.
ROUND_OFF = 1e-9
#: The half-height of such a panel, as a fraction of the largest torque of any joint.
FLAT_SPAN = 0.05


def new_figure(**options: Any) -> Figure:
    """A matplotlib ``Figure`` with an Agg canvas (no display, no pyplot state); ``options`` go to ``Figure``.

    The one place that imports matplotlib, so that importing the results does not.
    """
    import matplotlib.figure
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    figure = matplotlib.figure.Figure(**options)
    FigureCanvasAgg(figure)
    return figure


def _axis_values(joint: Joint, values: np.ndarray) -> tuple[np.ndarray, str]:
    if joint.kind == "prismatic":
        return values, f"{joint.name} [m]"
    return np.rad2deg(values), f"{joint.name} [deg]"


def torque_sweeps(result: EvaluatedDesign, points: int = 121) -> list[dict[str, Any]]:
    """Per moving joint: the sweep's joint values and that joint's torque before and after.

    Returns a list of ``{"joint", "values" (n) [rad or m], "before" (n), "after" (n)}``
    [N·m or N], in joint order; joints held fixed by the workspace are left out.
    """
    rows = []
    for joint in sweeps.moving_joints(result):
        workspace = sweeps.joint_sweep(result, joint.name, points)
        before = workspace.kinematics().gravity_torque[:, joint.index_v]
        after = result.evaluate_on(workspace).tau[:, joint.index_v]
        rows.append(
            {"joint": joint, "values": workspace.joint_values[:, joint.index_v], "before": before, "after": after}
        )
    return rows


def plot_torques(result: EvaluatedDesign, points: int = 121, path: str | Path | None = None) -> Figure:
    """Each joint's torque against its angle, before and after balancing (one panel per joint).

    ``path`` (optional): also save the figure there as PNG and SVG (see :func:`save_figure`).
    """
    rows = torque_sweeps(result, points)
    largest = largest_torque(*(np.concatenate([row["before"], row["after"]]) for row in rows))
    columns = min(len(rows), 3) or 1
    lines = int(np.ceil(len(rows) / columns)) or 1
    figure = new_figure(figsize=(4.2 * columns, 3.2 * lines), layout="constrained")
    if not rows:
        axes = figure.add_subplot()
        axes.text(0.5, 0.5, "the workspace holds every joint still: nothing to sweep", ha="center", va="center")
        axes.set_axis_off()
    for index, row in enumerate(rows):
        axes = figure.add_subplot(lines, columns, index + 1)
        joint = row["joint"]
        x, label = _axis_values(joint, row["values"])
        axes.plot(x, row["before"], color=BEFORE_COLOR, linestyle="--", label="gravity only")
        axes.plot(x, row["after"], color=AFTER_COLOR, linewidth=2, label="with springs")
        axes.axhline(0.0, color="black", linewidth=0.6)
        axes.set_xlabel(label)
        axes.set_ylabel(f"{joint.name} torque [{joint.torque_unit}]")
        axes.grid(True, alpha=0.3)
        flat_if_none(axes, np.concatenate([row["before"], row["after"]]), largest)
        say_if_unchanged(axes, row["before"], row["after"], largest)
        if index == 0:
            axes.legend(loc="best", fontsize="small")
    figure.suptitle(
        f"{result.problem.mechanism.name}: torque along a sweep of each joint (others at mid-range)", fontsize="medium"
    )
    if path is not None:
        save_figure(figure, path)
    return figure


def flat_if_none(axes: Any, values: np.ndarray, largest: float) -> None:
    """A panel of torques ``values`` [N·m or N] that are round-off (:func:`_carries_none`: the joint carries none)
    spans ±:data:`FLAT_SPAN` ``largest`` on its torque axis (y) and says so: on its own scale its round-off would
    look like a torque."""
    if _carries_none(values, largest):
        axes.set_ylim(-FLAT_SPAN * largest, FLAT_SPAN * largest)
        _say_none(axes)


def say_if_unchanged(axes: Any, before: np.ndarray, after: np.ndarray, largest: float) -> None:
    """A panel of a joint that gravity loads but the springs do not (every ``|after − before|`` within
    :data:`ROUND_OFF` of ``largest``, the largest torque of any joint [N·m or N]) says so: its "with springs" marks
    lie on the "gravity only" ones and hide them (a wrist beyond every spring's anchors); the panel's title says so."""
    if _carries_none(np.concatenate([before, after]), largest) or not _carries_none(after - before, largest):
        return
    axes.set_title("the springs do not act on this joint: before and after coincide", fontsize="small")  # over the data


def largest_torque(*torques: np.ndarray) -> float:
    """The largest magnitude [N·m or N] in any of the arrays ``torques`` (0 when they are empty)."""
    return float(max((np.max(np.abs(values), initial=0.0) for values in torques), default=0.0))


def _carries_none(values: np.ndarray, largest: float) -> bool:
    """Whether torques ``values`` [N·m or N] are round-off: every one within :data:`ROUND_OFF` of ``largest``, the
    largest torque of any joint."""
    return largest > 0.0 and float(np.max(np.abs(values))) <= ROUND_OFF * largest


def _say_none(axes: Any) -> None:
    axes.text(0.5, 0.8, "no gravity torque on this joint", transform=axes.transAxes, ha="center", fontsize="small")


def plot_histogram(result: EvaluatedDesign, bins: int = 40, path: str | Path | None = None) -> Figure:
    """Histogram of every joint's torque over the design's workspace samples, before and after. A joint that carries
    none (:func:`_carries_none`) is binned over ±:data:`FLAT_SPAN` of the largest torque of any joint, in an odd
    number of bins (its round-off in the one about zero), and says so."""
    problem = result.problem
    before = problem.workspace.kinematics().gravity_torque
    after = result.evaluation.tau
    largest = largest_torque(before, after)
    joints = problem.mechanism.joints
    columns = min(len(joints), 3)
    lines = int(np.ceil(len(joints) / columns))
    figure = new_figure(figsize=(4.2 * columns, 3.0 * lines), layout="constrained")
    for index, joint in enumerate(joints):
        axes = figure.add_subplot(lines, columns, index + 1)
        j = joint.index_v
        none = _carries_none(np.concatenate([before[:, j], after[:, j]]), largest)
        low = -FLAT_SPAN * largest if none else min(before[:, j].min(), after[:, j].min())
        high = FLAT_SPAN * largest if none else max(before[:, j].max(), after[:, j].max())
        count = bins + 1 if none and bins % 2 == 0 else bins  # (round-off in one bar about zero, not split at it)
        edges = np.linspace(low, high, count + 1) if high > low else bins
        axes.hist(
            before[:, j],
            bins=edges,  # type: ignore[arg-type]  # matplotlib stub: bins may be an array
            color=BEFORE_COLOR,
            alpha=0.55,
            label="gravity only",
        )
        axes.hist(
            after[:, j],
            bins=edges,  # type: ignore[arg-type]  # matplotlib stub: bins may be an array
            color=AFTER_COLOR,
            alpha=0.7,
            label="with springs",
        )
        axes.set_xlabel(f"{joint.name} torque [{joint.torque_unit}]")
        axes.set_ylabel("samples")
        axes.grid(True, alpha=0.3)
        if none:
            _say_none(axes)
        say_if_unchanged(axes, before[:, j], after[:, j], largest)
        if index == 0:
            axes.legend(loc="best", fontsize="small")
    figure.suptitle(
        f"{problem.mechanism.name}: torque over the {problem.workspace.size} workspace samples", fontsize="medium"
    )
    if path is not None:
        save_figure(figure, path)
    return figure


def save_figure(figure: Figure, path: str | Path, dpi: int = 110) -> list[Path]:
    """Save ``figure`` as ``<path>.png`` and ``<path>.svg`` (any suffix of ``path`` is replaced)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    written = []
    for suffix in (".png", ".svg"):
        target = path.with_suffix(suffix)
        figure.savefig(target, dpi=dpi)
        written.append(target)
    return written
