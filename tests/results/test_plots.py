"""Torque plots: the curves are the model's numbers, the files are real PNG and SVG."""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from scene_helpers import URDF, two_link_design
from springbalance.model import sweeps
from springbalance.results import plots
from springbalance.results.spread_plots import plot_residual_spread


@pytest.fixture(scope="module")
def design():
    return two_link_design()


def test_sweep_panels_show_the_model_torques(design):
    figure = design.plot_torques(points=31)
    axes = [a for a in figure.axes if a.lines]
    assert [a.get_xlabel() for a in axes] == ["shoulder [deg]", "elbow [deg]"]
    mechanism = design.problem.mechanism
    model, data = mechanism.model, mechanism.model.createData()
    lower, upper = sweeps.workspace_ranges(design)
    for axis, joint in zip(axes, mechanism.joints):
        before, after = axis.lines[0], axis.lines[1]
        assert before.get_label() == "gravity only" and after.get_label() == "with springs"
        angles = np.deg2rad(after.get_xdata())
        np.testing.assert_allclose(angles[[0, -1]], [lower[joint.index_v], upper[joint.index_v]])
        path = np.tile((lower + upper) / 2, (len(angles), 1))
        path[:, joint.index_v] = angles
        # after: the design's own residual torque; before: Pinocchio's gravity torque, independently
        np.testing.assert_allclose(after.get_ydata(), design.residual_torque(path)[:, joint.index_v], atol=1e-9)
        gravity = [pin.computeGeneralizedGravity(model, data, q)[joint.index_v] for q in mechanism.configurations(path)]
        np.testing.assert_allclose(before.get_ydata(), gravity, atol=1e-9)
        assert axis.get_ylabel() == f"{joint.name} torque [N·m]"


def test_a_joint_held_still_gets_no_panel():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.sobol(mechanism, 64, ranges={"shoulder": [-90, 90], "elbow": [0, 0]}, degrees=True)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.3, 0, 0)), stiffness=500.0
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    figure = plots.plot_torques(result, points=21)
    assert [a.get_xlabel() for a in figure.axes if a.lines] == ["shoulder [deg]"]


def test_histogram_counts_every_sample_before_and_after(design):
    figure = plots.plot_histogram(design, bins=12)
    size = design.problem.workspace.size
    for axis in figure.axes:
        before, after = axis.containers[0], axis.containers[1]
        assert sum(bar.get_height() for bar in before) == size
        assert sum(bar.get_height() for bar in after) == size
        assert len(before) == len(after) == 12
    assert [a.get_xlabel() for a in figure.axes] == ["shoulder torque [N·m]", "elbow torque [N·m]"]


def test_figures_are_written_as_png_and_svg(design, tmp_path):
    written = plots.save_figure(plots.plot_torques(design, points=21), tmp_path / "plots" / "torques.png")
    png, svg = written
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    root = ElementTree.parse(svg).getroot()
    assert root.tag.endswith("svg")
    text = svg.read_text()
    assert "shoulder" in text and "gravity only" in text
    from PIL import Image

    with Image.open(png) as image:
        width, height = image.size
        assert width > 400 and height > 200
        colours = np.asarray(image.convert("RGB")).reshape(-1, 3)
    # the "with springs" curve is drawn in its colour (#d7301f)
    assert np.count_nonzero(np.all(np.abs(colours.astype(int) - [0xD7, 0x30, 0x1F]) < 30, axis=1)) > 100


def test_importing_the_results_does_not_import_matplotlib():
    """matplotlib (0.2-0.4 s) is imported on the first figure (plots.new_figure), not at CLI start-up."""
    import subprocess
    import sys

    code = "import sys, springbalance.results.result; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


def test_new_figure_draws_on_an_agg_canvas():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    figure = plots.new_figure(figsize=(2.0, 1.5))
    assert isinstance(figure.canvas, FigureCanvasAgg) and tuple(figure.get_size_inches()) == (2.0, 1.5)


def test_a_joint_without_gravity_torque_is_plotted_flat_on_the_arms_scale():
    """a1 of the KR-like arm is vertical: its gravity torque is round-off, which on its own scale looks like a torque;
    its panel spans a twentieth of the largest torque and says there is none (the spring pulls from a point on that
    axis, so it adds no torque there either)."""
    mechanism = sb.Mechanism.from_urdf(URDF / "kr_like_6r.urdf")
    ranges = {"a1": [-90, 90], "a2": [-60, 60], "a3": [-60, 60], "a4": [0, 0], "a5": [0, 0], "a6": [0, 0]}
    workspace = sb.Workspace.sobol(mechanism, 64, ranges=ranges, degrees=True)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("base_link", (0, 0, 0.1)), sb.Anchor("link2", (0.2, 0, 0)), stiffness=1.0
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    figure = plots.plot_torques(result, points=21)
    axes = {a.get_xlabel(): a for a in figure.axes if a.lines}
    vertical = axes["a1 [deg]"]
    assert np.max(np.abs(vertical.lines[0].get_ydata())) < 1e-9  # Pinocchio's torque on a vertical axis: none
    largest = max(np.max(np.abs(line.get_ydata())) for a in axes.values() for line in a.lines[:2])
    assert largest > 10.0
    np.testing.assert_allclose(vertical.get_ylim(), (-plots.FLAT_SPAN * largest, plots.FLAT_SPAN * largest))
    assert [t.get_text() for t in vertical.texts] == ["no gravity torque on this joint"]
    lift = axes["a2 [deg]"]
    assert not lift.texts and lift.get_ylim()[1] - lift.get_ylim()[0] > 0.5 * largest
    # the histogram of the samples: a1's round-off in the bin about zero of a span a twentieth of the largest
    histogram = plots.plot_histogram(result, bins=12)
    panels = {a.get_xlabel(): a for a in histogram.axes}
    vertical, lift = panels["a1 torque [N·m]"], panels["a2 torque [N·m]"]
    workspace = result.problem.workspace
    residual = result.residual_torque(workspace.joint_values)
    sampled = max(np.max(np.abs(workspace.kinematics().gravity_torque)), np.max(np.abs(residual)))
    edges = [patch.get_x() for patch in vertical.containers[0]] + [
        vertical.containers[0][-1].get_x() + vertical.containers[0][-1].get_width()
    ]
    np.testing.assert_allclose(
        [edges[0], edges[-1]], [-plots.FLAT_SPAN * sampled, plots.FLAT_SPAN * sampled], rtol=1e-9
    )
    heights = [bar.get_height() for bar in vertical.containers[0]]
    assert len(heights) == 13  # an odd number of bins: one about zero, not two split at it
    assert heights[6] == result.problem.workspace.size  # every sample within the bin about zero
    assert [t.get_text() for t in vertical.texts] == ["no gravity torque on this joint"] and not lift.texts


def test_a_joint_the_springs_do_not_act_on_says_so_in_every_picture():
    """A spring from the ground to link1 of the two-link arm acts on the shoulder only: the elbow's torque with it
    is gravity's, to the last bit, so its "with springs" marks hide the "gravity only" ones. That panel's title says
    so in the sweep, the histogram and the spread; the shoulder's, which the spring changes, has none."""
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.sobol(mechanism, 64, ranges={"shoulder": [-90, 90], "elbow": [-90, 90]}, degrees=True)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.3, 0, 0)), stiffness=500.0
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    kinematics = workspace.kinematics()
    np.testing.assert_array_equal(result.evaluation.tau[:, 1], kinematics.gravity_torque[:, 1])  # the elbow: untouched
    assert np.max(np.abs(result.evaluation.tau[:, 0] - kinematics.gravity_torque[:, 0])) > 1.0  # the shoulder: not
    said = "the springs do not act on this joint: before and after coincide"
    sweep = {a.get_xlabel(): a.get_title() for a in plots.plot_torques(result, points=21).axes}
    assert sweep == {"shoulder [deg]": "", "elbow [deg]": said}
    histogram = {a.get_xlabel(): a.get_title() for a in plots.plot_histogram(result, bins=12).axes}
    assert histogram == {"shoulder torque [N·m]": "", "elbow torque [N·m]": said}
    spread = {a.get_xlabel(): a.get_title() for a in plot_residual_spread(result).axes}
    assert spread == {"shoulder [deg]": "", "elbow [deg]": said}
