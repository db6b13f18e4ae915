"""The tabulated spring (springs/laws/tabulated.py, docs/model.md §3.7): a law added as one module.

References here are independent of the law's code: NumPy's ``np.interp`` for the force inside the
table, the end segments' lines outside it, a trapezoid integral for the potential, and the closed-form
geometry of reference case R1 (urdf/single_link_r1.urdf) for the holding torque:
``tau = -m g s sin(phi) + F(L) Y_B r sin(phi) / L`` with ``L² = Y_B² + r² - 2 Y_B r cos(phi)``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.springs import SPRING_TYPES, spring_from_dict

URDF = Path(__file__).resolve().parents[2] / "urdf"
LAWS = Path(sb.__file__).parent / "springs" / "laws"
M1, S1, G1 = 8.0, 0.183, 9.81  # R1: link mass [kg], centre of mass [m], gravity [m/s²]
Y_B, R_A = 0.16, 0.3  # R1: ground anchor height, link anchor distance [m]
TABLE = [[0.10, 40.0], [0.20, 55.0], [0.30, 90.0], [0.45, 200.0]]  # a progressive curve [m], [N]


def _tabulated(**options):
    record = {
        "type": "tabulated",
        "a": {"body": "universe", "point": [0, 0, Y_B]},
        "b": {"body": "link1", "point": [0, 0, R_A]},
        "table": TABLE,
        **options,
    }
    return spring_from_dict(record)


def test_the_law_registers_itself_from_its_own_module():
    assert SPRING_TYPES["tabulated"].__module__ == "springbalance.springs.laws.tabulated"
    # nothing outside its module names it but the one line of the laws package that imports every law's
    # module: the registry does the rest
    for path in list(LAWS.parent.rglob("*.py")) + list((LAWS.parents[1] / "io").rglob("*.py")):
        if path == LAWS / "__init__.py":
            lines = [line for line in path.read_text().lower().splitlines() if "tabulated" in line]
            assert len(lines) == 1 and lines[0].startswith("from springbalance.springs.laws import "), lines
        elif path.name != "tabulated.py":
            assert "tabulated" not in path.read_text().lower(), path


def test_force_is_the_table_interpolated_and_extrapolated_with_the_end_slopes():
    spring = _tabulated()
    lengths, forces = np.array(TABLE).T
    inside = np.linspace(0.1, 0.45, 301)
    parameters = {"scale": 1.0, "shift": 0.0}
    np.testing.assert_allclose(spring.tension(inside, parameters), np.interp(inside, lengths, forces), atol=1e-9)
    low_slope, high_slope = (55 - 40) / 0.1, (200 - 90) / 0.15  # [N/m]
    np.testing.assert_allclose(spring.tension(np.array([0.05]), parameters), 40 - 0.05 * low_slope)
    np.testing.assert_allclose(spring.tension(np.array([0.5]), parameters), 200 + 0.05 * high_slope)
    # scale multiplies, shift moves the curve along the length
    np.testing.assert_allclose(
        spring.tension(inside + 0.02, {"scale": 3.0, "shift": 0.02}), 3 * np.interp(inside, lengths, forces), atol=1e-9
    )


def test_potential_is_the_integral_of_the_force():
    spring = _tabulated()
    parameters = {"scale": 2.0, "shift": 0.01}
    grid = np.linspace(0.11, 0.46, 20001)
    force = spring.tension(grid, parameters)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(grid))])  # [J]
    potential = spring.potential(grid, parameters)
    np.testing.assert_allclose(potential - potential[0], integral, atol=1e-6)
    np.testing.assert_allclose(spring.potential(np.array([0.11]), parameters), 0.0, atol=1e-12)  # zero at x0 + δ


def test_holding_torque_on_r1_matches_closed_form_geometry():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 121, ranges={"pivot": (2 * np.pi / 3, np.pi)})
    problem = sb.DesignProblem(mechanism, workspace, [_tabulated(scale=1.5, shift=0.25, stays_in_table=False)])
    tau = problem.evaluate(np.zeros(0)).tau[:, 0]
    phi = workspace.joint_values[:, 0]
    length = np.sqrt(Y_B**2 + R_A**2 - 2 * Y_B * R_A * np.cos(phi))
    lengths, forces = np.array(TABLE).T
    assert np.all((length - 0.25 >= lengths[0]) & (length - 0.25 <= lengths[-1]))  # inside the table
    force = 1.5 * np.interp(length - 0.25, lengths, forces)
    expected = -M1 * G1 * S1 * np.sin(phi) + force * Y_B * R_A * np.sin(phi) / length
    np.testing.assert_allclose(tau, expected, atol=1e-9)


def test_a_straight_table_through_zero_reproduces_r1a_exact_balance():
    """R1a: a zero-free-length spring balances the link exactly when ``k a b = m g s`` (k = 299.2 N/m)."""
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 121, ranges={"pivot": (2 * np.pi / 3, np.pi)})
    rate = 100.0  # [N/m] of the table's line
    spring = spring_from_dict(
        {
            "type": "tabulated",
            "a": {"body": "universe", "point": [0, 0, Y_B]},
            "b": {"body": "link1", "point": [0, 0, R_A]},
            "table": [[0.0, 0.0], [0.2, 0.2 * rate], [0.5, 0.5 * rate]],
            "scale": {"lower": 0, "upper": 10},
        }
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=2)
    expected_scale = M1 * G1 * S1 / (Y_B * R_A) / rate
    assert result.variables["s1.scale"] == pytest.approx(expected_scale, rel=1e-6)
    assert result.exact_balance()["exact"]


def test_stays_in_table_keeps_the_design_inside_the_table():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 61, ranges={"pivot": (2 * np.pi / 3, np.pi)})
    spring = spring_from_dict(
        {
            "type": "tabulated",
            "a": {"body": "universe", "point": [0, 0, Y_B]},
            "b": {"body": "link1", "point": [0, 0, R_A]},
            "table": TABLE,
            "scale": {"lower": 0, "upper": 10},
            "shift": {"lower": -0.3, "upper": 0.3},
        }
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=4)
    x = result.evaluation.lengths[:, 0] - result.variables["s1.shift"]
    assert x.min() >= TABLE[0][0] - 1e-6 and x.max() <= TABLE[-1][0] + 1e-6
    assert result.metrics()["joints"][0]["rms_after"] < 0.2 * result.metrics()["joints"][0]["rms_before"]


def test_record_round_trip_and_clear_errors():
    spring = _tabulated(scale={"lower": 0, "upper": 4}, shift=0.01)
    again = spring_from_dict(json.loads(json.dumps(spring.to_dict())))
    assert again.to_dict() == spring.to_dict()
    with pytest.raises(sb.InputError, match="missing key 'table'"):
        spring_from_dict({"type": "tabulated", "a": {"body": "universe"}, "b": {"body": "link1"}})
    with pytest.raises(sb.InputError, match="increase strictly; row 2"):
        _tabulated(table=[[0.1, 1.0], [0.2, 2.0], [0.2, 3.0]])
    with pytest.raises(sb.InputError, match="at least two rows"):
        _tabulated(table=[[0.1, 1.0]])
    with pytest.raises(sb.InputError, match="scale"):
        _tabulated(scale=-1.0)


def test_mujoco_export_holds_the_line_and_warns_of_the_curve(tmp_path):
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 61, ranges={"pivot": (2 * np.pi / 3, np.pi)})
    straight = spring_from_dict(
        {
            "type": "tabulated",
            "a": {"body": "universe", "point": [0, 0, Y_B]},
            "b": {"body": "link1", "point": [0, 0, R_A]},
            "table": [[0.0, 10.0], [0.3, 40.0], [0.6, 70.0]],
            "stays_in_table": False,
        }
    )
    report = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [straight]), np.zeros(0)).to_mjcf(
        tmp_path / "line.xml"
    )
    assert not any("nonlinear" in warning for warning in report.warnings)
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "line.xml"))
    assert model.tendon_stiffness[0] == pytest.approx(100.0)  # the table's slope [N/m]
    curved = _tabulated(stays_in_table=False)
    report = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [curved]), np.zeros(0)).to_mjcf(
        tmp_path / "curve.xml"
    )
    assert any("is nonlinear" in warning and "least-squares line" in warning for warning in report.warnings)
