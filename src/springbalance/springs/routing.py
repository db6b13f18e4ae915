r"""The length of a routed spring's path and its gradient (docs/model.md §3.9).

A path is the spring's fixed end ``P_0``, then pulleys or guide points ``P_1 … P_{m}``, then the
cable's end ``P_{m+1}`` (world positions [m]). Through guide points (radius 0) the cable runs
straight, and the length is :math:`\sum_i |P_{i+1} - P_i|`.

A pulley of radius ``r > 0`` at ``C`` between the path points ``A`` (before) and ``B`` (after)
is modelled as a **swivelling pulley**: it turns into the plane of ``A, C, B`` (as a pulley
on a swivel mount or a fairlead does) and the cable wraps round it on the outside of the bend.
With :math:`d_A = |A - C|`, :math:`d_B = |B - C|`, the angle :math:`\alpha` at ``C`` between
``A - C`` and ``B - C``, and :math:`\beta_X = \arccos(r/d_X)`, the cable from ``A`` to ``B`` is two
tangent segments and an arc of :math:`\varphi = 2\pi - \alpha - \beta_A - \beta_B`:

.. math:: \ell_{ACB} = \sqrt{d_A^2 - r^2} + \sqrt{d_B^2 - r^2} + r\,\varphi,

exact when ``A`` and ``B`` are points (path ends or guide points). The path length is the
straight path plus, per pulley, the correction :math:`\ell_{ACB} - d_A - d_B`. Between two
wrapping pulleys the correction of each is taken towards the other's *centre*, an error in
length of order :math:`r_1 r_2 / D` (``D`` the distance between their centres), which vanishes
when either radius does. Needs :math:`d_X > r` (the cable leaves the pulley) and a bend at the
pulley (:math:`\alpha < \pi`; a cable running straight past a pulley does not touch it).

The gradient :math:`\partial \ell / \partial P_i` (world, [1]) gives the force on each point:
the tension ``F`` [N] acts on point ``i`` as :math:`-F\,\partial\ell/\partial P_i` (towards its
neighbours), so the torque of the spring is :math:`F \sum_i J_{P_i}^T \partial\ell/\partial P_i`.
For the pulley correction,

.. math::
    \frac{\partial c}{\partial A} = \Bigl(\frac{s_A}{d_A} - 1\Bigr)\hat a
        + \frac{r\,(\hat b - \cos\alpha\,\hat a)}{d_A \sin\alpha}, \qquad
    \frac{\partial c}{\partial C} = -\frac{\partial c}{\partial A} - \frac{\partial c}{\partial B},

(and ``B`` alike), with :math:`s_X = \sqrt{d_X^2 - r^2}` and unit vectors :math:`\hat a, \hat b`
from ``C`` to ``A`` and ``B``.
"""

from __future__ import annotations

import math
from typing import Sequence, TypeVar

import casadi as ca

#: keeps ``sin α`` away from 0 in the pulley gradient (a straight cable: the ratio stays finite)
_TINY = 1e-12


#: the CasADi kind of one path (SX or MX, not mixed)
_Symbolic = TypeVar("_Symbolic", ca.SX, ca.MX)


def _norm(v: _Symbolic) -> _Symbolic:
    return ca.sqrt(ca.dot(v, v))


def path_length(points: Sequence, radii: Sequence[float]) -> tuple[object, list]:
    """Length [m] of the path through ``points`` (CasADi 3-vectors, world) and ``∂ℓ/∂P_i`` for each.

    ``radii[i]`` is the pulley radius [m] at point ``i`` (0 for a guide point; the ends' radii are
    ignored). Returns ``(length, gradients)``.
    """
    n = len(points)
    gradients = [ca.DM.zeros(3, 1) for _ in range(n)]
    length = 0
    for i in range(n - 1):
        d = points[i + 1] - points[i]
        segment = _norm(d)
        length = length + segment
        unit = d / segment
        gradients[i + 1] = gradients[i + 1] + unit
        gradients[i] = gradients[i] - unit
    for i in range(1, n - 1):
        r = float(radii[i])
        if r <= 0:
            continue
        a, b = points[i - 1] - points[i], points[i + 1] - points[i]
        d_a, d_b = _norm(a), _norm(b)
        a_hat, b_hat = a / d_a, b / d_b
        cosine = ca.dot(a_hat, b_hat)
        sine = _norm(ca.cross(a_hat, b_hat)) + _TINY
        alpha = ca.atan2(sine - _TINY, cosine)  # angle at the pulley [rad]
        s_a, s_b = ca.sqrt(d_a**2 - r**2), ca.sqrt(d_b**2 - r**2)  # tangent segments [m]
        wrap = 2 * math.pi - alpha - ca.acos(r / d_a) - ca.acos(r / d_b)  # arc on the pulley [rad]
        length = length + s_a + s_b + r * wrap - d_a - d_b
        grad_a = (s_a / d_a - 1) * a_hat + r * (b_hat - cosine * a_hat) / (d_a * sine)
        grad_b = (s_b / d_b - 1) * b_hat + r * (a_hat - cosine * b_hat) / (d_b * sine)
        gradients[i - 1] = gradients[i - 1] + grad_a
        gradients[i + 1] = gradients[i + 1] + grad_b
        gradients[i] = gradients[i] - grad_a - grad_b
    return length, gradients
