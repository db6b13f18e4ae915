"""The plots people expect, carrying what they claim:

- the spread plot: every workspace sample of each joint, its x the joint's own angle, "before" Pinocchio's
  gravity torque (independently), and a band that spans, in each bin of the angle, the least to the largest
  torque of the bin's samples (binned here on its own);
- the coil plot: the working range is the spring's shortest to longest length, here from the anchors' positions
  by Pinocchio's forward kinematics (and equal to the spec sheet's); the law is Shigley's rate
  k = G d⁴/(8 D³ n) (music wire G = 81.0 GPa, Table 10-5) from the free length; the allowable force is where
  the Bergsträsser-corrected stress K_B 8 F D/(π d³), K_B = (4C + 2)/(4C − 3), reaches the allowable;
- the tolerance band: in each bin, the least and largest residual over all 8² corner builds of a two-spring
  design, each evaluated as a design of its own (brute force, as tests/design/test_tolerance.py);
- the report shows them, and the text report prints a count (active coils) without a unit "1".
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pinocchio as pin
import pytest

import springbalance as sb
from scene_helpers import URDF, two_link_design
from springbalance.results import plots
from springbalance.results.coil_plots import plot_coils
from springbalance.results.html_report import write_report
from springbalance.results.spread_plots import plot_residual_spread, plot_tolerance_band
from springbalance.springs.laws.helical_compression import HelicalCompressionSpring
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
from tolerance_helpers import LAWS, SPEC, corner_laws, two_springs

G_MUSIC = 81.0e9  # [Pa] Shigley Table 10-5, music wire 1.62–3.18 mm


def _by_gid(axes, gid):
    return [artist for artist in axes.collections + axes.lines + axes.patches if artist.get_gid() == gid]


def _extent(band, x: float) -> tuple[float, float]:
    """The band's vertical extent at ``x``: where the vertical line through x crosses its outline."""
    ys = []
    for path in band.get_paths():
        vertices = path.vertices
        for (x0, y0), (x1, y1) in itertools.pairwise(vertices):
            if x0 != x1 and min(x0, x1) <= x <= max(x0, x1):
                ys.append(y0 + (y1 - y0) * (x - x0) / (x1 - x0))
    return min(ys), max(ys)


def _expected_bins(x: np.ndarray, low: np.ndarray, high: np.ndarray, bins: int):
    """Per bin of equal width over [min x, max x] (the last closed): (midpoint, least low, largest high)."""
    width = (x.max() - x.min()) / bins
    index = np.minimum(np.floor((x - x.min()) / width).astype(int), bins - 1)
    return [
        (x.min() + (b + 0.5) * width, low[index == b].min(), high[index == b].max())
        for b in range(bins)
        if (index == b).any()
    ]


def test_spread_plot_shows_every_sample_and_its_band():
    design = two_link_design()
    figure = plot_residual_spread(design, bins=5)
    mechanism = design.problem.mechanism
    values = design.problem.workspace.joint_values
    data = mechanism.model.createData()
    gravity = np.array(
        [pin.computeGeneralizedGravity(mechanism.model, data, q) for q in mechanism.configurations(values)]
    )
    after = design.residual_torque(values)
    panels = [axes for axes in figure.axes if axes.collections]
    assert [axes.get_xlabel() for axes in panels] == ["shoulder [deg]", "elbow [deg]"]
    for axes, joint in zip(panels, mechanism.joints):
        j = joint.index_v
        (before_points,) = _by_gid(axes, "before-points")
        (after_points,) = _by_gid(axes, "after-points")
        angles = np.rad2deg(values[:, j])
        np.testing.assert_allclose(before_points.get_offsets(), np.column_stack([angles, gravity[:, j]]), atol=1e-9)
        np.testing.assert_allclose(after_points.get_offsets(), np.column_stack([angles, after[:, j]]), atol=1e-9)
        for gid, torque in (("before-band", gravity[:, j]), ("after-band", after[:, j])):
            (band,) = _by_gid(axes, gid)
            for middle, low, high in _expected_bins(angles, torque, torque, 5):
                assert _extent(band, middle) == pytest.approx((low, high), abs=1e-9)


def _coil_design():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.grid(mechanism, 6, ranges={"shoulder": [-70, 70], "elbow": [-60, 60]}, degrees=True)
    d, D, n = 2.5e-3, 20e-3, 30.0
    springs = [
        HelicalExtensionSpring(
            sb.Anchor("universe", (0.0, 0.0, 0.25)), sb.Anchor("link1", (0.3, 0.0, 0.0)), "pull",
            wire_diameter=d, mean_diameter=D, active_coils=n, initial_tension=15.0,
        ),
        HelicalCompressionSpring(
            sb.Anchor("universe", (0.0, 0.0, -0.1)), sb.Anchor("link1", (0.2, 0.0, 0.0)), "push",
            wire_diameter=d, mean_diameter=D, active_coils=12.0, free_length=0.3,
        ),
    ]  # fmt: skip
    problem = sb.DesignProblem(mechanism, workspace, springs)
    return sb.DesignResult(problem, np.zeros(0)), (d, D)


def _lengths(design, a, b):
    """Anchor-to-anchor distance at every sample, by Pinocchio's frame placements."""
    mechanism = design.problem.mechanism
    model, data = mechanism.model, mechanism.model.createData()
    out = []
    for q in mechanism.configurations(design.problem.workspace.joint_values):
        pin.framesForwardKinematics(model, data, q)
        ends = [data.oMf[model.getFrameId(body)].act(np.array(point)) if body != "universe" else np.array(point)
                for body, point in (a, b)]  # fmt: skip
        out.append(np.linalg.norm(ends[1] - ends[0]))
    return np.array(out)


def test_coil_plot_working_range_law_and_allowable_force():
    design, (d, D) = _coil_design()
    figure = plot_coils(design)
    panels = [axes for axes in figure.axes if axes.lines]
    assert len(panels) == 2
    ends = {
        "pull": (("universe", (0, 0, 0.25)), ("link1", (0.3, 0, 0))),
        "push": (("universe", (0, 0, -0.1)), ("link1", (0.2, 0, 0))),
    }
    index = D / d
    k_b = (4 * index + 2) / (4 * index - 3)
    for axes, record in zip(panels, design.springs):
        sheet = record["helical"]
        lengths = _lengths(design, *ends[record["name"]])
        (span,) = _by_gid(axes, "working-range")
        xs = np.array([span.get_x(), span.get_x() + span.get_width()])  # data x (the y spans the axes)
        assert (xs.min(), xs.max()) == pytest.approx((1e3 * lengths.min(), 1e3 * lengths.max()), rel=1e-9)
        assert (xs.min(), xs.max()) == pytest.approx((1e3 * sheet["shortest_length"], 1e3 * sheet["longest_length"]))
        (allowable,) = _by_gid(axes, "allowable")
        force = sheet["allowable_stress"] * math.pi * d**3 / (8 * k_b * D)
        assert allowable.get_ydata()[0] == pytest.approx(force, rel=1e-9)
        n = 30.0 if record["name"] == "pull" else 12.0
        rate = G_MUSIC * d**4 / (8 * D**3 * n)
        (law,) = _by_gid(axes, "law")
        length, pull = 1e-3 * law.get_xdata(), law.get_ydata()
        if record["name"] == "pull":
            assert length.min() == pytest.approx(sheet["free_length"])
            np.testing.assert_allclose(pull, 15.0 + rate * (length - length.min()), rtol=1e-9)
            assert {"hook-bending", "hook-torsion"} <= {line.get_gid() for line in axes.lines}
        else:
            assert (length.min(), length.max()) == pytest.approx((d * (12 + 2), 0.3))
            np.testing.assert_allclose(pull, rate * (0.3 - length), rtol=1e-9, atol=1e-12)
            assert _by_gid(axes, "solid")
        # every sample sits on the law
        (samples,) = _by_gid(axes, "samples")
        points = samples.get_offsets()
        np.testing.assert_allclose(np.sort(points[:, 0]), np.sort(1e3 * lengths), rtol=1e-9)
        expected = (
            15.0 + rate * (1e-3 * points[:, 0] - sheet["free_length"])
            if record["name"] == "pull"
            else (rate * (0.3 - 1e-3 * points[:, 0]))
        )
        np.testing.assert_allclose(points[:, 1], expected, rtol=1e-6)


def test_tolerance_band_is_the_brute_force_envelope_of_every_build():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    rng = np.random.default_rng(5)
    workspace = sb.Workspace.from_array(mechanism, rng.uniform(-1.2, 1.2, size=(60, 2)))
    design = sb.DesignResult(sb.DesignProblem(mechanism, workspace, two_springs(LAWS)), np.zeros(0), tolerance=SPEC)
    builds = [
        sb.DesignProblem(mechanism, workspace, two_springs(laws)).evaluate(np.zeros(0)).tau for _, laws in corner_laws()
    ]
    stack = np.stack(builds)
    figure = plot_tolerance_band(design, bins=6)
    panels = [axes for axes in figure.axes if axes.collections]
    for axes, joint in zip(panels, mechanism.joints):
        j = joint.index_v
        angles = np.rad2deg(workspace.joint_values[:, j])
        (band,) = _by_gid(axes, "tolerance-band")
        for middle, low, high in _expected_bins(angles, stack[:, :, j].min(axis=0), stack[:, :, j].max(axis=0), 6):
            assert _extent(band, middle) == pytest.approx((low, high), abs=1e-9)
        (nominal,) = _by_gid(axes, "nominal-points")
        np.testing.assert_allclose(nominal.get_offsets()[:, 1], design.evaluation.tau[:, j], atol=1e-12)
    # no spring with a box (ideal laws under the default grade: no coil to grade): no plot
    assert plot_tolerance_band(two_link_design()) is None


def test_the_report_shows_the_plots_and_the_text_report_prints_counts_bare(tmp_path):
    design, _ = _coil_design()
    write_report(design, tmp_path, scene=False)
    page = (tmp_path / "report.html").read_text()
    for name in ("spread", "coils", "tolerance"):
        assert f'<img src="{name}.svg"' in page
        assert (tmp_path / f"{name}.svg").is_file() and (tmp_path / f"{name}.png").is_file()
    text = design.table()
    assert "active_coils 30  initial_tension 15 N" in text and "active_coils 12  free_length 0.3 m" in text


def test_a_joint_without_gravity_torque_is_flat_in_the_spread_and_tolerance_plots():
    """a1 of the KR-like arm is vertical, and the extension spring pulls from a point on its axis: a1's torques are
    round-off. In the spread plot and the tolerance band its panel spans a twentieth of the largest torque of any
    joint and says there is none; a2's (the shoulder pitch) keeps its own scale."""
    mechanism = sb.Mechanism.from_urdf(URDF / "kr_like_6r.urdf")
    ranges = {"a1": [-90, 90], "a2": [-60, 60], "a3": [-60, 60], "a4": [0, 0], "a5": [0, 0], "a6": [0, 0]}
    workspace = sb.Workspace.sobol(mechanism, 64, ranges=ranges, degrees=True)
    spring = sb.ExtensionSpring(
        sb.Anchor("base_link", (0, 0, 0.1)), sb.Anchor("link2", (0.2, 0, 0)), "s", stiffness=300.0, free_length=0.1
    )
    design = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0), tolerance=SPEC)
    gravity = workspace.kinematics().gravity_torque
    residual = design.residual_torque(workspace.joint_values)
    assert np.max(np.abs(gravity[:, 0])) < 1e-9 and np.max(np.abs(residual[:, 0])) < 1e-9  # the premise
    largest = max(np.max(np.abs(gravity)), np.max(np.abs(residual)))  # of any joint, at the samples
    for name, figure in [
        ("spread", plot_residual_spread(design, bins=5)),
        ("band", plot_tolerance_band(design, bins=5)),
    ]:
        panels = {axes.get_xlabel(): axes for axes in figure.axes}
        vertical, pitch = panels["a1 [deg]"], panels["a2 [deg]"]
        low, high = vertical.get_ylim()
        assert low == -high
        if name == "spread":  # the samples' torques: the largest is this one
            assert high == pytest.approx(plots.FLAT_SPAN * largest, rel=1e-12)
        else:  # the band holds the nominal residual, and spreads wider
            assert plots.FLAT_SPAN * largest <= high < 3 * plots.FLAT_SPAN * largest
        assert [text.get_text() for text in vertical.texts] == ["no gravity torque on this joint"]
        assert not pitch.texts and pitch.get_ylim()[1] - pitch.get_ylim()[0] > 4 * high
