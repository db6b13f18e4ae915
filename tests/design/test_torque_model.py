"""The per-sample torque model against closed-form statics of a single pendulum (docs/model.md §2-§4).

urdf/single_link_r1.urdf: one link of mass m = 8 kg about the world x axis, centre of mass at s = 0.183 m on
the link's +z axis, gravity (0, 0, -9.81). At joint angle q the link point (0, 0, r) is at the world point
(0, -r sin q, r cos q), so

- gravity: V_g = m g s cos q [J], g(q) = ∂V_g/∂q = -m g s sin q [N·m];
- a zero-free-length spring of stiffness k from the ground point B = (0, 0, b) to the link point
  A = (0, 0, a): L² = a² + b² - 2 a b cos q [m²], tension F = k L [N], V_s = k L²/2 [J] and
  τ_s = ∂V_s/∂q = k a b sin q [N·m];
- residual torque τ = g(q) + τ_s = (k a b - m g s) sin q, zero at every pose when k a b = m g s.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.torque_model import TorqueModel

ROOT = Path(__file__).resolve().parents[2]
MASS, COM, GRAVITY = 8.0, 0.183, 9.81  # [kg], [m], [m/s²], as in the URDF


@pytest.fixture(scope="module")
def pendulum():
    mechanism = sb.Mechanism.from_urdf(ROOT / "urdf" / "single_link_r1.urdf")
    q = np.linspace(2.0943951023931953, np.pi, 7)[:, None]
    return mechanism, sb.Workspace.from_array(mechanism, q), q[:, 0]


def _outputs(mechanism, workspace, springs):
    model = TorqueModel(mechanism, springs)
    assert model.variables.size == 0  # every parameter fixed: the model is a function of the samples only
    return model, model.evaluate(np.zeros(0), model.data_matrix(workspace.kinematics()))


@pytest.mark.parametrize("k, a, b", [(500.0, 0.3, 0.16), (1200.0, 0.25, 0.05)])
def test_a_zero_free_length_spring_on_a_pendulum(pendulum, k, a, b):
    mechanism, workspace, q = pendulum
    spring = sb.ZeroFreeLengthSpring(sb.Anchor("ground", [0.0, 0.0, b]), sb.Anchor("link1", [0.0, 0.0, a]), stiffness=k)
    model, out = _outputs(mechanism, workspace, [spring])
    length = np.sqrt(a * a + b * b - 2 * a * b * np.cos(q))
    np.testing.assert_allclose(out["L"][:, 0], length, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(out["F"][:, 0], k * length, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(out["tau"][:, 0], (k * a * b - MASS * GRAVITY * COM) * np.sin(q), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(out["V"], MASS * GRAVITY * COM * np.cos(q) + 0.5 * k * length**2, rtol=1e-9, atol=1e-9)
    assert model.n_springs == 1


def test_the_balancing_stiffness_leaves_no_torque(pendulum):
    mechanism, workspace, q = pendulum
    a, b = 0.3, 0.16
    k = MASS * GRAVITY * COM / (a * b)  # k a b = m g s
    spring = sb.ZeroFreeLengthSpring(sb.Anchor("ground", [0.0, 0.0, b]), sb.Anchor("link1", [0.0, 0.0, a]), stiffness=k)
    _, out = _outputs(mechanism, workspace, [spring])
    np.testing.assert_allclose(out["tau"][:, 0], 0.0, atol=1e-10)
    # V = m g s cos q + k (a² + b²)/2 - k a b cos q: the cos q terms cancel
    np.testing.assert_allclose(out["V"], 0.5 * k * (a * a + b * b), rtol=1e-12)


def test_without_springs_the_torque_is_the_weight_moment(pendulum):
    mechanism, workspace, q = pendulum
    _, out = _outputs(mechanism, workspace, [])
    np.testing.assert_allclose(out["tau"][:, 0], -MASS * GRAVITY * COM * np.sin(q), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(out["V"], MASS * GRAVITY * COM * np.cos(q), rtol=1e-12, atol=1e-12)


def test_a_free_anchor_is_a_design_variable(pendulum):
    """A free link anchor (box region) adds its three coordinates [m] as design variables; at x = A the
    model gives the fixed spring's numbers."""
    mechanism, workspace, q = pendulum
    k, a, b = 500.0, 0.3, 0.16
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("ground", [0.0, 0.0, b]), sb.Anchor("link1", sb.Free([-0.1, -0.1, 0.0], [0.1, 0.1, 0.5])), stiffness=k
    )
    model = TorqueModel(mechanism, [spring])
    assert model.variables.size == 3 and all(unit == "m" for unit in model.variables.units)
    out = model.evaluate(np.array([0.0, 0.0, a]), model.data_matrix(workspace.kinematics()))
    np.testing.assert_allclose(out["tau"][:, 0], (k * a * b - MASS * GRAVITY * COM) * np.sin(q), rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize(
    "name, module",
    [
        ("_LeastSquaresResiduals", "residuals"),
        ("_MultiStartSolver", "multistart"),
        ("_StartRunner", "pool"),
        ("_pool_workers", "pool"),
    ],
)
def test_the_moved_solver_names_still_work_and_warn(name, module):
    import importlib

    from springbalance.design import solvers

    with pytest.warns(
        DeprecationWarning, match=f"solvers.{name} is deprecated; use springbalance.design.solvers.{module}"
    ):
        value = getattr(solvers, name)
    assert value is getattr(importlib.import_module(f"springbalance.design.solvers.{module}"), name)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        from springbalance.design.solvers import solve_problem, start_points, workers_default  # noqa: F401  (not moved)
