"""The warnings weak_design (springbalance.results.weak_design), beyond_joint_limits and off_series_wire
(springbalance.results.range_flags), each provoked by a small real problem; they are warnings: the design
still passes (result.ok).

The single link (urdf/single_link_r1.urdf): m = 8 kg, centre of mass c = 0.183 m, URDF limits of its
joint ``pivot`` [2π/3, π] rad = [120°, 180°]. A spring from a = 0.16 m above the pivot to b along the
link balances it exactly when its force is k·L (zero free length) with k·a·b = m·g·c (docs/model.md §9);
an ideal extension spring with free initial tension F0 = k·l0 is such a spring, so the ideal twin of a
coil on these anchors removes the whole torque.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from flag_helpers import SLIDER_URDF, assert_flagged
from springbalance.design.standard_wire import WireRounding
from springbalance.design.twin import TwinRecord
from springbalance.io.config import load_config
from springbalance.results.range_flags import beyond_joint_limits
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring

URDF = Path(__file__).resolve().parents[2] / "urdf"

#: a music-wire coil within a 4 mm outer diameter: the thickest wire that fits, 0.8 mm, with 200 coils
#: carries only a fraction of the 8 kg link's pull, so the coil rules, not the anchors, limit the balance
WEAK = """
mechanism: {{urdf: {urdf}}}
workspace: {{kind: grid, n: 16}}
springs:
  - name: s1
    type: extension
    a: {{body: universe, point: [0, 0, 0.16]}}
    b: {{body: link1, box: {{lower: [0, 0, 0.05], upper: [0, 0, 0.4]}}}}
    material: music_wire
    max_outer_diameter: {envelope}
solve: {{starts: 1, seed: 0}}
"""


def _solved(tmp_path: Path, envelope: float) -> sb.DesignResult:
    path = tmp_path / f"weak_{envelope}.yaml"
    path.write_text(WEAK.format(urdf=URDF / "single_link_r1.urdf", envelope=envelope))
    return sb.solve(load_config(path), progress=False)


# ---------------------------------------------------------------------- weak_design
def test_a_coil_in_a_tight_envelope_is_weak_and_names_what_binds(tmp_path):
    result = _solved(tmp_path, 0.004)
    twin = result.twin
    assert isinstance(twin, TwinRecord)
    # the ideal twin balances exactly (see the module docstring): it removes the whole rms torque
    assert twin.objective <= 1e-6 * twin.objective_before and twin.joints["pivot"] > 99.9
    objective = result.metrics()["objectives"]["rms"]
    assert objective["before"] == pytest.approx(twin.objective_before, rel=1e-12)
    assert objective["reduction_percent"] < 50
    record = assert_flagged(result, tmp_path, "weak_design", "design")
    assert result.ok  # a warning: the design still passes
    assert f"remove {objective['reduction_percent']:.1f} % of the rms objective" in record["message"]
    assert "their ideal twin removes" in record["message"]
    # the rules that bind are the coil's: a rule row of s1 or one of its coil variables at a bound
    binding = record["message"].split("the rules that bind: ")[1].split(", ")
    assert binding and all(rule.startswith("s1") for rule in binding), binding
    assert any(rule.startswith("s1: ") for rule in binding), binding
    # the twin's record is saved under solver.twin and loaded back (not on another workspace)
    loaded = sb.DesignResult.load(tmp_path / "design.json")
    assert loaded.twin == twin
    assert [flag.kind for flag in loaded.warnings()] == [flag.kind for flag in result.warnings()]
    mechanism = loaded.problem.mechanism
    other = sb.DesignResult.load(tmp_path / "design.json", mechanism, sb.Workspace.grid(mechanism, 7))
    assert other.twin is None and "weak_design" not in [flag.kind for flag in other.warnings()]


def test_a_coil_with_room_is_not_weak(tmp_path):
    result = _solved(tmp_path, 0.04)
    assert result.twin is not None
    assert result.metrics()["objectives"]["rms"]["reduction_percent"] > 50
    assert "weak_design" not in [flag.kind for flag in result.warnings()]


def test_no_twin_no_weak_design():
    # an ideal spring capped at a third of k* removes a third of the torque, but an ideal unconstrained
    # design has no twin to compare with
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.16)), sb.Anchor("link1", (0, 0, 0.3)), "s1", stiffness=100.0
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, sb.Workspace.grid(mechanism, 31), [spring]), np.zeros(0))
    assert result.twin is None and "weak_design" not in [flag.kind for flag in result.warnings()]
    # with a twin that removes everything, the same design is weak: 1 − 100/299.2 = 66.6 % of the torque
    # remains at every sample
    twin = TwinRecord("a test twin", 0.0, result.metrics()["objectives"]["rms"]["before"], {"pivot": 100.0})
    weak = sb.DesignResult(result.problem, np.zeros(0), twin=twin)
    (flag,) = [flag for flag in weak.warnings() if flag.kind == "weak_design"]
    k_star = 8.0 * 9.81 * 0.183 / (0.16 * 0.3)
    assert f"remove {100 * 100 / k_star:.1f} %" in flag.message and "pivot 33.4 % (twin 100.0 %)" in flag.message


# ---------------------------------------------------------------------- beyond_joint_limits
def test_a_workspace_beyond_the_urdf_limits_is_flagged(tmp_path):
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    # 31 samples over [90°, 180°], 3° apart: 90°, 93°, …, 117° (10 samples) lie below the limit of 120°
    workspace = sb.Workspace.grid(mechanism, 31, ranges={"pivot": (math.pi / 2, math.pi)})
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.16)), sb.Anchor("link1", (0, 0, 0.3)), "s1", stiffness=sb.Free(0, 1000)
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=1, progress=False)
    record = assert_flagged(result, tmp_path, "beyond_joint_limits", "pivot")
    assert "10 of 31 samples outside" in record["message"]
    assert "[1.571, 3.142] rad ([90.0°, 180.0°])" in record["message"]
    assert "limits [2.094, 3.142] rad ([120.0°, 180.0°])" in record["message"]
    assert result.ok
    # within the limits: nothing
    inside = sb.Workspace.grid(mechanism, 31)
    assert beyond_joint_limits(mechanism, inside.joint_values) == []


def test_prismatic_limits_in_metres_and_continuous_joints_have_none(tmp_path):
    path = tmp_path / "slider.urdf"
    path.write_text(SLIDER_URDF)
    mechanism = sb.Mechanism.from_urdf(path)
    (flag,) = beyond_joint_limits(mechanism, np.array([[0.05, 0.0], [0.2, 0.0], [0.35, 0.0]]))
    assert flag.subject == "slide" and "[0.05, 0.35] m" in flag.message and "2 of 3 samples" in flag.message
    continuous = SLIDER_URDF.replace('type="revolute"', 'type="continuous"')
    path.write_text(continuous)
    wheel = sb.Mechanism.from_urdf(path)
    # far beyond the revolute limit of ±90°, but a continuous joint has none
    assert beyond_joint_limits(wheel, np.array([[0.2, 3.0], [0.2, -3.0]])) == []


# ---------------------------------------------------------------------- off_series_wire
def _coil(wire: float) -> HelicalExtensionSpring:
    return HelicalExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.16]),
        sb.Anchor("link1", [0, 0, 0.3]),
        "c1",
        wire_diameter=wire,
        mean_diameter=12 * wire,
        active_coils=20.0,
        initial_tension=1.0,
    )


def test_a_wire_off_the_preferred_series_is_flagged(tmp_path):
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 31)
    # 1.05 mm lies between the preferred 1.0 and 1.1 mm; 1.0 mm is one of them
    off = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [_coil(1.05e-3)]), np.zeros(0))
    record = assert_flagged(off, tmp_path, "off_series_wire", "c1")
    assert "wire of 1.05 mm, not a preferred size" in record["message"]
    on = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [_coil(1.0e-3)]), np.zeros(0))
    assert "off_series_wire" not in [flag.kind for flag in on.warnings()]
    # the rounding's reason for leaving it continuous is quoted
    rounding = WireRounding(1.0, 1.0, {}, {"c1": "no preferred size within its bounds"})
    left = sb.DesignResult(off.problem, np.zeros(0), wire_rounding=rounding)
    (flag,) = [flag for flag in left.warnings() if flag.kind == "off_series_wire"]
    assert flag.message.endswith("the rounding left it: no preferred size within its bounds")
