r"""Textbook relations of helical coil springs of round wire (numbers, arrays and CasADi expressions).

A helical spring of round wire (diameter ``d``), mean coil diameter ``D``, index
``C = D/d`` and ``n`` active coils, of a wire with shear modulus ``G``:

.. math::
    k = \frac{G d^4}{8 D^3 n},\qquad
    \tau = K_W \frac{8 F D}{\pi d^3},\qquad
    K_W = \frac{4C - 1}{4C - 4} + \frac{0.615}{C},

rate ``k`` [N/m], shear stress ``τ`` [Pa] at the inside of the coil under axial force ``F``
[N], with the Wahl factor ``K_W`` (direct shear plus curvature). References (Shigley's
Mechanical Engineering Design, Budynas & Nisbett, 9th ed. 2011 / 10th ed. 2015, chapter 10):
Eq. (10-9): rate; Eq. (10-5): Wahl factor; Eq. (10-6): Bergsträsser factor
``K_B = (4C + 2)/(4C − 3)`` (the two differ by less than 1 %); Eq. (10-34)–(10-36): the stresses
in a machine hook; Eq. (10-40): the preferred initial stress of an extension spring.

Every quantity is in SI units (m, N, Pa, kg).
"""

from __future__ import annotations

import math
from typing import Any, Callable

import casadi as ca
import numpy as np

from springbalance.springs.values import ValueT

MPA = 1e6  # [Pa]
MM = 1e-3  # [m]


# ---------------------------------------------------------------------- textbook relations
def wahl_factor(index: ValueT) -> ValueT:
    r"""Wahl factor :math:`K_W = (4C - 1)/(4C - 4) + 0.615/C` (Shigley Eq. 10-5), dimensionless."""
    return (4 * index - 1) / (4 * index - 4) + 0.615 / index


def bergstrasser_factor(index: ValueT) -> ValueT:
    r"""Bergsträsser factor :math:`K_B = (4C + 2)/(4C - 3)` (Shigley Eq. 10-6), dimensionless."""
    return (4 * index + 2) / (4 * index - 3)


def spring_rate(
    shear_modulus: float | ValueT, wire_diameter: ValueT, mean_diameter: ValueT, active_coils: float | ValueT
) -> ValueT:
    r"""Rate :math:`k = G d^4 / (8 D^3 n)` [N/m] (Shigley Eq. 10-9); G [Pa], d and D [m]."""
    return shear_modulus * wire_diameter**4 / (8 * mean_diameter**3 * active_coils)


def shear_stress(
    force: float | ValueT, wire_diameter: ValueT, mean_diameter: ValueT, factor: Callable[[Any], Any] = wahl_factor
) -> ValueT:
    r"""Corrected shear stress :math:`\tau = K \, 8 F D / (\pi d^3)` [Pa] under axial force F [N].

    ``factor`` maps the index ``C = D/d`` to the correction (default the Wahl factor).
    """
    return factor(mean_diameter / wire_diameter) * 8 * force * mean_diameter / (math.pi * wire_diameter**3)


def coil_mass(
    stiffness: ValueT,
    coil_diameter: float,
    active_coils: float,
    wire_length: float,
    shear_modulus: float,
    density: float,
) -> ValueT:
    r"""Mass [kg] of a coil of fixed ``D`` and ``n`` whose wire diameter gives rate ``k``
    (docs/model.md §5): :math:`m_s = \rho \pi L_w \sqrt{D^3 n k / (2 G)}`.

    From :math:`k = G d^4/(8 D^3 n)`, :math:`d^2 = \sqrt{8 D^3 n k / G}` and
    :math:`m_s = \rho L_w \pi d^2 / 4`. Works on numbers and CasADi expressions.
    """
    return density * math.pi * wire_length * (coil_diameter**3 * active_coils * stiffness / (2 * shear_modulus)) ** 0.5


def initial_stress_band(index: ValueT) -> tuple[ValueT, ValueT]:
    r"""Preferred range ``(low, high)`` [Pa] of the uncorrected initial stress of a close-wound
    extension spring of index ``C`` (Shigley Eq. 10-40, fitted to the wire makers' chart):

    .. math:: \tau_i = \frac{231}{e^{0.105 C}} \pm 6.9\Bigl(4 - \frac{C - 3}{6.5}\Bigr)\ \mathrm{MPa},

    with :math:`\tau_i = 8 F_i D / (\pi d^3)` for an initial tension ``F_i`` [N]. Works on numbers,
    arrays and CasADi expressions.
    """
    middle = 231.0 * MPA * _exp(-0.105 * index)  # [Pa]
    half_width = 6.9 * MPA * (4.0 - (index - 3.0) / 6.5)  # [Pa]
    return middle - half_width, middle + half_width


def hook_bending_stress(force: float | ValueT, wire_diameter: ValueT, mean_diameter: ValueT) -> ValueT:
    r"""Bending stress [Pa] at the top of a machine hook (section A, Shigley Eq. 10-34, 10-35), with the
    hook's bend index ``C_1 = 2 r_1/d = D/d`` (the hook as wide as the coil):

    .. math:: \sigma_A = F\Bigl[(K)_A \frac{16 D}{\pi d^3} + \frac{4}{\pi d^2}\Bigr],\qquad
              (K)_A = \frac{4 C_1^2 - C_1 - 1}{4 C_1 (C_1 - 1)} .
    """
    c1 = mean_diameter / wire_diameter
    factor = (4 * c1 * c1 - c1 - 1) / (4 * c1 * (c1 - 1))
    return force * (factor * 16 * mean_diameter / (math.pi * wire_diameter**3) + 4 / (math.pi * wire_diameter**2))


#: bend index ``C_2 = 2 r_2 / d`` of the side bend of a machine hook (section B); Shigley asks for C_2 > 4.
HOOK_SIDE_BEND_INDEX = 4.0


def hook_torsion_stress(
    force: float | ValueT, wire_diameter: ValueT, mean_diameter: ValueT, side_bend_index: float = HOOK_SIDE_BEND_INDEX
) -> ValueT:
    r"""Torsional stress [Pa] at the side bend of a machine hook (section B, Shigley Eq. 10-36):
    :math:`\tau_B = (K)_B\, 8 F D/(\pi d^3)`, :math:`(K)_B = (4 C_2 - 1)/(4 C_2 - 4)`."""
    factor = (4 * side_bend_index - 1) / (4 * side_bend_index - 4)
    return factor * 8 * force * mean_diameter / (math.pi * wire_diameter**3)


def _exp(value: ValueT) -> ValueT:
    return ca.exp(value) if isinstance(value, (ca.SX, ca.MX, ca.DM)) else np.exp(value)


def select(condition: Any, if_true: Any, if_false: Any) -> Any:
    """``if_true`` where ``condition`` holds, else ``if_false``: ``ca.if_else`` on CasADi expressions,
    ``np.where`` on numbers and arrays."""
    if isinstance(condition, (ca.SX, ca.MX, ca.DM)) or isinstance(if_true, (ca.SX, ca.MX)):
        return ca.if_else(condition, if_true, if_false)
    return np.where(condition, if_true, if_false)
