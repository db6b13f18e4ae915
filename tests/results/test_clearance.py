"""Clearance check of a finished design: springs as capsules against the URDF's collision geometry.

The arm is urdf/two_link_planar_collision.urdf: two_link_planar.urdf with collision shapes equal
to its visuals (link1: box 0.5×0.04×0.04 m centred 0.25 m along x; link2: box 0.4×0.03×0.03 m
centred 0.2 m along x; tool: sphere of radius 0.03 m 0.4 m along link2). Both joints turn about
(0, -1, 0). The expected distances are computed here from that geometry, independently of
Pinocchio and coal.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import springbalance as sb
from flag_helpers import fixed_design
from springbalance.cli import main
from springbalance.results.clearance import ClearanceReport

URDF = Path(__file__).resolve().parents[2] / "urdf"
LINK2_HALF = np.array([0.2, 0.015, 0.015])  # half extents of link2's box [m]
TOOL_RADIUS = 0.03  # [m]


@pytest.fixture(scope="module")
def arm():
    return sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")


design = fixed_design


def rotation(angle):
    """Rotation about (0, -1, 0) by ``angle`` [rad]: +x turns towards +z."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def link_placement(body, shoulder, elbow):
    """World rotation and origin of ``body``'s frame at the pose (planar forward kinematics)."""
    if body == "universe":
        return np.eye(3), np.zeros(3)
    r1 = rotation(shoulder)
    if body == "link1":
        return r1, np.zeros(3)
    r2, elbow_origin = rotation(shoulder + elbow), r1 @ np.array([0.5, 0.0, 0.0])
    if body == "link2":
        return r2, elbow_origin
    raise KeyError(body)


def world(body, point, shoulder, elbow):
    r, t = link_placement(body, shoulder, elbow)
    return t + r @ np.asarray(point, dtype=float)


def segment_distance(start, end, point_distance):
    """Smallest ``point_distance`` over the segment (a convex function of the fraction along it)."""
    along = lambda t: point_distance(start + t * (end - start))  # noqa: E731
    best = minimize_scalar(along, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-12})
    return min(float(best.fun), along(0.0), along(1.0))


def analytic_clearance(start, end, shoulder, elbow):
    """Distances [m] from the segment to link2's box and to the tool's sphere (no radius)."""
    r2, t2 = link_placement("link2", shoulder, elbow)
    box_centre, tool_centre = t2 + r2 @ np.array([0.2, 0, 0]), t2 + r2 @ np.array([0.4, 0, 0])

    def to_box(p):
        local = r2.T @ (p - box_centre)
        return float(np.linalg.norm(local - np.clip(local, -LINK2_HALF, LINK2_HALF)))

    return {
        "link2": segment_distance(start, end, to_box),
        "tool": segment_distance(start, end, lambda p: float(np.linalg.norm(p - tool_centre)) - TOOL_RADIUS),
    }


# ---------------------------------------------------------------------- a spring through link 2
THROUGH = dict(a=("universe", [0.7, 0.0, 0.2]), b=("link1", [0.45, 0.0, -0.1]))


def through_spring():
    return sb.ExtensionSpring(
        sb.Anchor(*THROUGH["a"]), sb.Anchor(*THROUGH["b"]), "through", stiffness=100.0, free_length=0.05
    )


def test_a_spring_through_link2_overlaps_it(arm):
    # At the straight pose the line from (0.7, 0, 0.2) to (0.45, 0, -0.1) crosses z = 0 at
    # x = 0.7 - 0.25 * 0.2 / 0.3 = 0.533 m, inside link2's box (x 0.5 ... 0.9 m, |y|, |z| ≤ 0.015 m).
    start, end = world(*THROUGH["a"], 0, 0), world(*THROUGH["b"], 0, 0)
    t = start[2] / (start[2] - end[2])
    crossing = start + t * (end - start)
    assert 0.5 < crossing[0] < 0.9 and crossing[1] == 0 and crossing[2] == pytest.approx(0, abs=1e-15)

    report = design(arm, [through_spring()], [[0.0, 0.0], [0.6, -1.0]]).clearance(margin=0.005)
    row = report.row("through")
    assert row.link == "link2" and row.geometry == "link2_0"
    assert row.distance < 0 and row.below_margin and not report.clear
    # the segment lies in the box's mid-plane y = 0: the shortest way out is sideways, along y,
    # by the box's half width plus the capsule radius
    assert row.distance == pytest.approx(-(LINK2_HALF[1] + 0.01), abs=1e-6)
    assert row.pose == {"shoulder": 0.0, "elbow": 0.0} and row.sample == 0
    # the universe and link1 are exempt (link1's box holds the b end)
    assert row.exempt == ("universe", "link1")


def test_a_clear_spring_reports_the_segment_box_distance_minus_its_radius(arm):
    # above the arm and off its plane, slanted; link2 comes closest when the shoulder rises and the elbow drops
    a, b = ("universe", [0.55, 0.05, 0.25]), ("link1", [0.35, -0.02, 0.09])
    spring = sb.ExtensionSpring(sb.Anchor(*a), sb.Anchor(*b), "clear", stiffness=100.0, free_length=0.05)
    poses = np.array([[0.0, 0.0], [0.1, -0.4], [-0.2, 0.3], [0.3, -0.6]])
    radius = 0.007
    report = design(arm, [spring], poses).clearance(radius=radius, margin=0.01)

    expected = []  # (distance, link, sample)
    for sample, (shoulder, elbow) in enumerate(poses):
        distances = analytic_clearance(world(*a, shoulder, elbow), world(*b, shoulder, elbow), shoulder, elbow)
        expected += [(distance - radius, link, sample) for link, distance in distances.items()]
    distance, link, sample = min(expected)
    row = report.row("clear")
    assert distance > 0.01
    assert row.radius == radius
    assert row.distance == pytest.approx(distance, abs=1e-6)
    assert (row.link, row.sample) == (link, sample)
    assert row.pose == pytest.approx(dict(zip(["shoulder", "elbow"], poses[sample])))
    assert not row.below_margin and report.clear
    # a larger margin flags it
    assert design(arm, [spring], poses).clearance(radius=radius, margin=distance + 1e-3).row("clear").below_margin


def test_the_anchor_bodies_are_exempt(arm):
    # along the links' axis from link1 to link2: the segment runs inside both boxes (exempt), and
    # the tool, welded to link2 but a body of its own, is 0.4 - 0.2 m beyond the b end at every pose
    spring = sb.ExtensionSpring(
        sb.Anchor("link1", [0.1, 0, 0]), sb.Anchor("link2", [0.2, 0, 0]), "along", stiffness=100.0, free_length=0.05
    )
    report = design(arm, [spring], [[0.0, 0.0], [0.5, -1.2], [-1.0, 2.0]]).clearance()
    row = report.row("along")
    assert row.exempt == ("link1", "link2")
    assert row.link == "tool"
    assert row.distance == pytest.approx(0.2 - TOOL_RADIUS - 0.01, abs=1e-9)


def test_samples_check_a_sobol_sample_of_the_workspace_ranges(arm):
    poses = [[-0.4, 0.2], [0.5, -0.3], [0.1, 0.0]]
    report = design(arm, [through_spring()], poses).clearance(samples=64)
    assert report.poses == 64
    pose = report.row("through").pose
    assert -0.4 <= pose["shoulder"] <= 0.5 and -0.3 <= pose["elbow"] <= 0.2
    assert report.row("through").link == "link2"


def test_a_helical_spring_uses_half_its_outer_diameter(arm):
    coil = sb.HelicalExtensionSpring(
        sb.Anchor(*THROUGH["a"]),
        sb.Anchor(*THROUGH["b"]),
        "coil",
        wire_diameter=2e-3,
        mean_diameter=16e-3,
        active_coils=20,
        initial_tension=5.0,
    )
    result = design(arm, [coil], [[0.0, 0.0]])
    outer = result.spring("coil")["helical"]["outer_diameter"]
    assert outer == pytest.approx(18e-3)
    row = result.clearance(radius=0.05).row("coil")  # the radius argument is for springs without a sheet
    assert row.radius == pytest.approx(outer / 2)
    assert row.distance == pytest.approx(-(LINK2_HALF[1] + outer / 2), abs=1e-6)


def test_report_text_and_dict(arm):
    report = design(arm, [through_spring()], [[0.0, 0.0]]).clearance()
    assert isinstance(report, ClearanceReport)
    text = "\n".join(report.lines())
    assert "through" in text and "link2" in text and "OVERLAP" in text and "-25.0" in text
    record = json.loads(json.dumps(report.to_dict()))
    assert record["rows"][0]["link"] == "link2" and record["clear"] is False
    assert record["collision_objects"] == ["link1_0", "link2_0", "tool_0"]


def test_a_mechanism_without_collision_geometry_is_refused():
    bare = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.3, 0, 0]), "s1", stiffness=100.0, free_length=0.05
    )
    with pytest.raises(sb.InputError, match="'two_link_planar' has no collision geometry"):
        design(bare, [spring], [[0.0, 0.0]]).clearance()
    model_only = sb.Mechanism.from_model(bare.model)
    with pytest.raises(sb.InputError, match="'two_link_planar' was not loaded from a URDF"):
        design(model_only, [spring], [[0.0, 0.0]]).clearance()


def test_a_mechanisms_collision_geometry_is_loaded_once_and_errors_every_time(arm):
    """Every fit and verification asks for the arm's collision geometry: it is loaded once per mechanism (the same
    model each time; another mechanism of the same URDF loads its own), and an arm without any is refused at every
    ask, not only the first."""
    from springbalance.model.collision import collision_geometry

    geometry = collision_geometry(arm)
    assert geometry.ngeoms > 0 and collision_geometry(arm) is geometry
    again = sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")
    assert collision_geometry(again) is not geometry and collision_geometry(again).ngeoms == geometry.ngeoms
    bare = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    for _ in range(2):
        with pytest.raises(sb.InputError, match="'two_link_planar' has no collision geometry"):
            collision_geometry(bare)


def test_bad_arguments_are_input_errors(arm):
    result = design(arm, [through_spring()], [[0.0, 0.0]])
    for options in (
        {"radius": 0.0},
        {"radius": float("nan")},
        {"margin": float("inf")},
        {"margin": -0.001},
        {"samples": 0},
    ):
        with pytest.raises(sb.InputError):
            result.clearance(**options)


def test_reports_carry_the_clearance_table_when_the_urdf_has_collision_geometry(arm, tmp_path):
    result = design(arm, [through_spring()], [[0.0, 0.0], [0.6, -1.0]])
    text = result.table()
    assert "Clearance of the springs to the collision geometry" in text and "OVERLAP" in text
    page = result.report(tmp_path, scene=False).read_text()
    assert 'id="clearance"' in page and "link2" in page and "overlap" in page
    # without collision geometry there is nothing to check, and the reports say nothing of it
    bare = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    plain = design(bare, [through_spring()], [[0.0, 0.0]])
    assert "Clearance of the springs" not in plain.table()
    assert 'id="clearance"' not in plain.report(tmp_path / "bare", scene=False).read_text()


# ---------------------------------------------------------------------- command line
def test_cli_prints_the_table(arm, tmp_path, capsys):
    path = tmp_path / "design.json"
    design(arm, [through_spring()], [[0.0, 0.0], [0.2, 0.3]]).save(path)
    # the spring runs through link2: the check fails (exit 3, a design that fails a check) and says where
    assert main(["clearance", str(path), "--samples", "32", "--margin", "0.01", "--radius", "0.012"]) == 3
    out = capsys.readouterr().out
    assert "over 32 poses" in out and "margin 10.0 mm" in out
    line = next(line for line in out.splitlines() if line.startswith("through"))
    assert line.split()[:5] == ["through", "12.0", "-27.0", "link2", "OVERLAP"]
    assert "1 of 1 springs below the margin (through)" in out


@pytest.mark.parametrize("argv", [["missing.json"], ["design.json", "--radius", "-1"]])
def test_cli_bad_input_is_one_line_and_exit_2(arm, tmp_path, capsys, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    design(arm, [through_spring()], [[0.0, 0.0]]).save(tmp_path / "design.json")
    assert main(["clearance", *argv]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("springbalance: error: ")
