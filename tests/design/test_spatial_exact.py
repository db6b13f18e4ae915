"""The exact test of spatial balance: multilinear coefficients of the potential (docs/model.md §9.1).

Expected values are derived by hand (tests/spatial_helpers.py) or built independently of the code.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import springbalance as sb
from spatial_helpers import M3, WEIGHT_MOMENT, G, H, yaw_pitch_roll
from springbalance import exact
from springbalance.design.exact.multilinear import GRID, coefficients_of


def test_a_random_multilinear_function_is_recovered_exactly():
    rng = np.random.default_rng(3)
    truth = rng.normal(size=(3, 3, 3, 3))
    values = []
    for angles in itertools.product(GRID, repeat=4):
        factors = [np.array([1.0, np.cos(t), np.sin(t)]) for t in angles]
        values.append(sum(truth[i] * np.prod([f[a] for f, a in zip(factors, i)]) for i in np.ndindex(truth.shape)))
    assert np.max(np.abs(coefficients_of(np.array(values), 4) - truth)) < 1e-12


def test_gravity_coefficients_of_the_hand_derived_arm():
    offset = 0.05
    result = exact.spatial_coefficients(yaw_pitch_roll(offset), [])
    expected = np.zeros((3, 3, 3))
    expected[0, 2, 0] = -G * WEIGHT_MOMENT  # sin θ₂ (axes: yaw, pitch, roll; 0, 1, 2 = 1, cos, sin)
    expected[0, 1, 2] = G * M3 * offset  # cos θ₂ sin θ₃
    got = result.coefficients.copy()
    got[0, 0, 0] = 0.0  # the constant: not a condition
    assert np.max(np.abs(got - expected)) < 1e-12
    assert result.gravity_scale == pytest.approx(G * WEIGHT_MOMENT, rel=1e-12)
    assert set(result.terms()) == {"sin pitch", "cos pitch · sin roll"}


def _spring(a: float, b: float, stiffness: float) -> sb.ZeroFreeLengthSpring:
    return sb.ZeroFreeLengthSpring(
        sb.Anchor("ground", (0.0, 0.0, H + a)), sb.Anchor("link2", (b, 0.0, 0.0)), stiffness=stiffness
    )


def test_the_balanced_arm_is_exact_and_a_moved_anchor_is_not():
    arm = yaw_pitch_roll()
    a, b = 0.2, 0.25
    k = G * WEIGHT_MOMENT / (a * b)  # k a b = g (M2 C2 + M3 (L2 + C3))
    balanced = exact.spatial_coefficients(arm, [_spring(a, b, k)])
    assert balanced.exact and balanced.relative < 1e-13
    moved = sb.ZeroFreeLengthSpring(
        sb.Anchor("ground", (0.01, 0.0, H + a)), sb.Anchor("link2", (b, 0.0, 0.0)), stiffness=k
    )
    off = exact.spatial_coefficients(arm, [moved])
    assert not off.exact
    # the ground point e = 1 cm off the yaw axis adds −k e b cos θ₁ cos θ₂ (the cross term of L²)
    assert list(off.terms()) == ["cos yaw · cos pitch"]
    assert off.largest == pytest.approx(k * 0.01 * b, rel=1e-9)


def test_the_balanced_arm_has_zero_torque_in_pinocchio():
    arm = yaw_pitch_roll()
    a, b = 0.2, 0.25
    k = G * WEIGHT_MOMENT / (a * b)
    ws = sb.Workspace.sobol(arm, 64, ranges={"yaw": [-3, 3], "pitch": [-3, 3], "roll": [-3, 3]}, seed=2)
    result = sb.DesignResult(sb.DesignProblem(arm, ws, [_spring(a, b, k)]), np.zeros(0))
    assert exact.spatial_coefficients(result).exact
    assert result.exact_balance()["relative_residual"] < 1e-12
    # a problem with the stiffness free, and its design vector
    free = sb.ZeroFreeLengthSpring(
        sb.Anchor("ground", (0.0, 0.0, H + a)), sb.Anchor("link2", (b, 0.0, 0.0)), stiffness=sb.Free(0, 2 * k)
    )
    problem = sb.DesignProblem(arm, ws, [free])
    assert len(problem.variables.names) == 1  # the stiffness
    assert exact.spatial_coefficients(problem, np.array([k])).exact
    assert not exact.spatial_coefficients(problem, np.array([1.01 * k])).exact


def test_refuses_what_is_not_multilinear():
    arm = yaw_pitch_roll()
    extension = sb.ExtensionSpring(
        sb.Anchor("ground", (0, 0, 0.5)), sb.Anchor("link2", (0.2, 0, 0)), stiffness=100.0, free_length=0.1
    )
    with pytest.raises(sb.InputError, match="zero-free-length"):
        exact.spatial_coefficients(arm, [extension])
    free = sb.ZeroFreeLengthSpring(
        sb.Anchor("ground", (0, 0, 0.5)), sb.Anchor("link2", (0.2, 0, 0)), stiffness=sb.Free(0, 10)
    )
    with pytest.raises(sb.InputError, match="free anchors or stiffness"):
        exact.spatial_coefficients(arm, [free])
