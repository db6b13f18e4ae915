"""Stiffnesses for fixed anchors by non-negative least squares (exact.fit_stiffnesses).

The arm and its balancing spring are derived by hand in tests/spatial_helpers.py: a ground point on the
yaw axis ``a`` above the pitch joint and a link-2 point ``b`` along the link balance exactly when
``k a b = g (M2 C2 + M3 (L2 + C3))``.
"""

from __future__ import annotations

import numpy as np
import pytest

import springbalance as sb
from spatial_helpers import WEIGHT_MOMENT, G, H, yaw_pitch_roll
from springbalance import exact


def _candidate(ground: tuple, link: tuple, name: str) -> sb.ZeroFreeLengthSpring:
    return sb.ZeroFreeLengthSpring(
        sb.Anchor("ground", ground), sb.Anchor("link2", link), name=name, stiffness=sb.Free(0, 1)
    )


def test_the_fit_finds_the_balancing_spring_among_distractors():
    a, b = 0.2, 0.25
    rng = np.random.default_rng(5)
    candidates = [_candidate((0, 0, H + a), (b, 0, 0), "right")]
    candidates += [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("ground", tuple(rng.uniform(-0.3, 0.3, 3))),
            sb.Anchor(body, tuple(rng.uniform(-0.3, 0.3, 3))),
            name=f"d{i}",
            stiffness=100.0,
        )
        for i, body in enumerate(["link1", "link2", "link3", "link3"])
    ]
    fit = exact.fit_stiffnesses(yaw_pitch_roll(), candidates)
    assert fit.exact and fit.relative < 1e-10
    assert fit.stiffness[0] == pytest.approx(G * WEIGHT_MOMENT / (a * b), rel=1e-9)
    assert np.all(fit.stiffness[1:] < 1e-9 * fit.stiffness[0])
    assert [spring.name for spring in fit.springs] == ["right"]


def test_anchors_off_the_axis_cannot_balance_whatever_the_stiffness():
    # the ground end 5 cm off the yaw axis: k a b sin θ₂ balances, but −k e b cos θ₁ cos θ₂ remains; the
    # best k trades one against the other (least squares on the two coefficients g·WM and k·b·√(a² + e²)...)
    a, b, e = 0.2, 0.25, 0.05
    fit = exact.fit_stiffnesses(yaw_pitch_roll(), [_candidate((e, 0, H + a), (b, 0, 0), "off")])
    assert not fit.exact
    # min over k of (g WM − k a b)² + (k e b)²: k = g WM a / (b (a² + e²)), residual g WM e / √(a² + e²)
    assert fit.stiffness[0] == pytest.approx(G * WEIGHT_MOMENT * a / (b * (a**2 + e**2)), rel=1e-9)
    assert fit.residual == pytest.approx(G * WEIGHT_MOMENT * e / np.hypot(a, e), rel=1e-9)


def test_a_free_anchor_is_refused():
    free = sb.ZeroFreeLengthSpring(
        sb.Anchor("ground", sb.Free([-1] * 3, [1] * 3)), sb.Anchor("link2", (0.1, 0, 0)), stiffness=1.0
    )
    with pytest.raises(sb.InputError, match="free anchor"):
        exact.fit_stiffnesses(yaw_pitch_roll(), [free])
