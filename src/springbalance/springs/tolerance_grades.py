r"""Quality grades of cold-coiled helical springs (docs/model.md §3.10): the permissible deviations of
EN 15800 (ex DIN 2095, compression springs) and DIN 2097 (extension springs), grades 1, 2 and 3.

Every function takes and returns SI units (m, N, N/m); the standards' formulas and tables are in mm
and N and are converted here. With wire diameter ``d``, mean coil diameter ``D``, index
``w = D/d``, ``n`` active coils and rate ``R`` [N/mm], EN 15800 (2008) §4 gives

.. math::

    \alpha_F = 65.92\,\frac{d^{3.3}}{D^{1.6}}
        \left[-0.84\left(\tfrac{w}{10}\right)^3 + 3.781\left(\tfrac{w}{10}\right)^2
              - 4.244\,\tfrac{w}{10} + 2.274\right]\ \text{[N]},\qquad
    k_F = \frac{1}{3 n^2} + \frac{8}{5 n} + 0.803,

    A_F = \pm\left(\alpha_F k_F + \frac{1.5\,F}{100}\right) Q\ \text{[N]},\qquad
    A_{L0} = \pm\frac{\alpha_F k_F Q}{R}\ \text{[mm]},

with the quality factor ``Q`` = 0.63, 1.0, 1.6 for grades 1, 2, 3 (grade 2 when the drawing says
nothing, DIN 2099). ``A_F`` bounds the force at a test length, ``A_L0`` the free length of a
compression spring. The mean-diameter deviation ``A_D`` is a table over ``D`` and ``w``, the same in
EN 15800 and DIN 2097 (:data:`COIL_DIAMETER_TABLE`). DIN 2097 tolerances an extension spring's
forces from the same α_F and k_F diagrams (reproduced here by the EN 15800 regression) and its body
length ``L0`` from a table over ``L0`` and ``w`` given for grade 2 (:data:`EXTENSION_FREE_LENGTH_TABLE`);
grades 1 and 3 scale it by ``Q`` (our assumption: the table is quoted for grade 2 only).

Sources (docs/model.md §3.10): the formulas of EN 15800:2008 §4 as reproduced in the EN15800 unit of
the open-source spring designer ``melchiorrecaruso/springone``; the ``A_D`` table on Gutekunst
Federn's page https://blog.federnshop.com/en/tension-spring-tolerances/ (DIN 2097, also EN 15800);
the extension free-length table (grade 2) on
https://www.industrial-springs.com/faq/extension-springs/what-tolerances-does-an-extension-spring-have.

The balance model reads the force tolerance as two parts with the structure of the formula: a
proportional part ``1.5 % · Q`` of the force (the rate's deviation) and a constant part
``α_F k_F Q`` [N] (a length error: ``A_L0 = α_F k_F Q / R``). :func:`grade_box` returns them as the
± on rate, initial tension and free length of the law, so that the worst force over the box at every
length is exactly ``A_F`` there.
"""

from __future__ import annotations

import bisect
import math
import numbers
from dataclasses import dataclass
from typing import Any, Literal

import casadi as ca

from springbalance.errors import InputError

MM = 1e-3  # [m]
#: quality factor Q per grade (EN 15800 §4, DIN 2097)
QUALITY_FACTORS: dict[int, float] = {1: 0.63, 2: 1.0, 3: 1.6}
#: the grade that holds when a drawing gives none (DIN 2099)
DEFAULT_GRADE = 2
#: proportional part of the force tolerance per unit Q [1] (the ``1.5 F / 100`` term)
PROPORTIONAL_FORCE = 0.015

#: ``A_D`` [mm]: rows (D_low, D_high] in mm, then grade 1, 2, 3, each at index w in [4, 8], (8, 14], (14, 20]
COIL_DIAMETER_TABLE: tuple[tuple[float, float, tuple[float, ...], tuple[float, ...], tuple[float, ...]], ...] = (
    (0.63, 1.0, (0.05, 0.07, 0.10), (0.07, 0.10, 0.15), (0.10, 0.15, 0.20)),
    (1.0, 1.6, (0.05, 0.07, 0.10), (0.08, 0.10, 0.15), (0.15, 0.20, 0.30)),
    (1.6, 2.5, (0.07, 0.10, 0.15), (0.10, 0.15, 0.20), (0.20, 0.30, 0.40)),
    (2.5, 4.0, (0.10, 0.10, 0.15), (0.15, 0.20, 0.25), (0.30, 0.40, 0.50)),
    (4.0, 6.3, (0.10, 0.15, 0.20), (0.20, 0.25, 0.30), (0.40, 0.50, 0.60)),
    (6.3, 10.0, (0.15, 0.15, 0.20), (0.25, 0.30, 0.35), (0.50, 0.60, 0.70)),
    (10.0, 16.0, (0.15, 0.20, 0.25), (0.30, 0.35, 0.40), (0.60, 0.70, 0.80)),
    (16.0, 25.0, (0.20, 0.25, 0.30), (0.35, 0.45, 0.50), (0.70, 0.90, 1.00)),
    (25.0, 31.5, (0.25, 0.30, 0.35), (0.40, 0.50, 0.60), (0.80, 1.00, 1.20)),
    (31.5, 40.0, (0.25, 0.30, 0.35), (0.50, 0.60, 0.70), (1.00, 1.20, 1.50)),
    (40.0, 50.0, (0.30, 0.40, 0.50), (0.60, 0.80, 0.90), (1.20, 1.50, 1.80)),
    (50.0, 63.0, (0.40, 0.50, 0.60), (0.80, 1.00, 1.10), (1.50, 2.00, 2.30)),
    (63.0, 80.0, (0.50, 0.70, 0.80), (1.00, 1.20, 1.40), (1.80, 2.40, 2.80)),
    (80.0, 100.0, (0.60, 0.80, 0.90), (1.20, 1.50, 1.70), (2.30, 3.00, 3.50)),
    (100.0, 125.0, (0.70, 1.00, 1.10), (1.40, 1.90, 2.20), (2.80, 3.70, 4.40)),
    (125.0, 160.0, (0.90, 1.20, 1.40), (1.80, 2.30, 2.70), (3.50, 4.60, 5.40)),
    (160.0, 200.0, (1.20, 1.50, 1.70), (2.10, 2.90, 3.30), (4.20, 5.70, 6.60)),
)
#: DIN 2097 grade 2 ``A_L0`` [mm] of an extension spring: rows (upper L0 [mm], at w in [4, 8], at w in (8, 20]);
#: above 400 mm the deviation is 1.5 % of L0
EXTENSION_FREE_LENGTH_TABLE: tuple[tuple[float, float, float], ...] = (
    (10.0, 0.40, 0.50),
    (16.0, 0.50, 0.60),
    (25.0, 0.60, 0.70),
    (40.0, 0.80, 0.90),
    (63.0, 1.10, 1.30),
    (100.0, 1.50, 1.80),
    (160.0, 2.00, 2.40),
    (250.0, 2.50, 3.00),
    (400.0, 3.00, 4.00),
)
#: the relative deviation of an extension spring longer than the table [1]
EXTENSION_FREE_LENGTH_BEYOND = 0.015

Kind = Literal["compression", "extension"]


def quality_factor(grade: int) -> float:
    """The quality factor ``Q`` of a grade (1 → 0.63, 2 → 1.0, 3 → 1.6); InputError for any other grade."""
    if isinstance(grade, bool) or grade not in QUALITY_FACTORS:
        raise InputError(f"tolerance grade must be 1, 2 or 3 (EN 15800 / DIN 2097), got {grade!r}")
    return QUALITY_FACTORS[int(grade)]


def alpha_f(wire_diameter: Any, mean_diameter: Any) -> Any:
    r"""EN 15800 factor :math:`\alpha_F` [N] of wire ``d`` [m] and mean coil diameter ``D`` [m]
    (the formula in mm; the index is clamped to the standard's 4–20)."""
    d, D = wire_diameter / MM, mean_diameter / MM
    x = _clamp(D / d, 4.0, 20.0) / 10
    return 65.92 * d**3.3 / D**1.6 * (-0.84 * x**3 + 3.781 * x**2 - 4.244 * x + 2.274)


def k_f(active_coils: Any) -> Any:
    r"""EN 15800 factor :math:`k_F = 1/(3 n^2) + 8/(5 n) + 0.803` [1] of ``n`` active coils (n ≥ 2)."""
    n = _clamp(active_coils, 2.0, math.inf)
    return 1 / (3 * n * n) + 8 / (5 * n) + 0.803


def _clamp(value: Any, low: float, high: float) -> Any:
    """``value`` within ``[low, high]``: a number, or a CasADi expression (the robust design's symbols)."""
    if isinstance(value, numbers.Real):
        return min(max(float(value), low), high)
    return ca.fmin(ca.fmax(value, low), high)


def force_tolerance(
    wire_diameter: float, mean_diameter: float, active_coils: float, force: float, grade: int = DEFAULT_GRADE
) -> float:
    r"""Permissible deviation ``A_F`` [N] of the force ``F`` [N] at a test length (EN 15800; DIN 2097):
    :math:`(\alpha_F k_F + 1.5 |F| / 100)\,Q`."""
    constant = alpha_f(wire_diameter, mean_diameter) * k_f(active_coils)
    return (constant + PROPORTIONAL_FORCE * abs(force)) * quality_factor(grade)


def coil_diameter_tolerance(wire_diameter: float, mean_diameter: float, grade: int = DEFAULT_GRADE) -> float:
    """Permissible deviation ``A_D`` [m] of the mean (and so the outer or inner) coil diameter, from the
    EN 15800 / DIN 2097 table; ``D`` outside 0.63–200 mm and ``w`` outside 4–20 take the nearest row/column."""
    quality_factor(grade)  # validates the grade
    D, w = mean_diameter / MM, mean_diameter / wire_diameter
    uppers = [row[1] for row in COIL_DIAMETER_TABLE]
    row = COIL_DIAMETER_TABLE[min(bisect.bisect_left(uppers, D), len(uppers) - 1)]
    column = 0 if w <= 8 else 1 if w <= 14 else 2
    by_grade = {1: row[2], 2: row[3], 3: row[4]}
    return by_grade[int(grade)][column] * MM


def free_length_tolerance(
    kind: Kind,
    wire_diameter: float,
    mean_diameter: float,
    active_coils: float,
    free_length: float,
    rate: float,
    grade: int = DEFAULT_GRADE,
) -> float:
    r"""Permissible deviation ``A_L0`` [m] of the free length ``L0`` [m] (rate ``R`` [N/m]).

    Compression (EN 15800): :math:`\alpha_F k_F Q / R`. Extension (DIN 2097): the grade 2 table over
    ``L0`` and ``w`` (1.5 % of ``L0`` above 400 mm), times ``Q`` for grades 1 and 3.
    """
    Q = quality_factor(grade)
    if kind == "compression":
        return alpha_f(wire_diameter, mean_diameter) * k_f(active_coils) * Q / rate
    if kind != "extension":
        raise InputError(f"tolerance: spring kind must be 'compression' or 'extension', got {kind!r}")
    L0, w = free_length / MM, mean_diameter / wire_diameter
    for upper, low_index, high_index in EXTENSION_FREE_LENGTH_TABLE:
        if L0 <= upper:
            return (low_index if w <= 8 else high_index) * Q * MM
    return EXTENSION_FREE_LENGTH_BEYOND * free_length * Q


def initial_tension_tolerance(
    wire_diameter: float,
    mean_diameter: float,
    active_coils: float,
    initial_tension: float,
    grade: int = DEFAULT_GRADE,
) -> float:
    """Deviation [N] of an extension spring's initial tension ``F_i`` [N]: the force tolerance at the
    free length, ``A_F(F_i)`` (the force there is ``F_i``)."""
    return force_tolerance(wire_diameter, mean_diameter, active_coils, initial_tension, grade)


@dataclass(frozen=True)
class GradeBox:
    """The ± of a coil's law under a grade: ``rate`` [1, fraction of k], ``initial_tension`` [N],
    ``free_length`` [m] (the law's box, see :func:`grade_box`), and the part's ``coil_diameter`` [m]
    and ``free_length_dimension`` [m] (the drawing's tolerances, for the order form)."""

    grade: int
    rate: float
    initial_tension: float
    free_length: float
    coil_diameter: float
    free_length_dimension: float


def grade_box(
    kind: Kind,
    wire_diameter: float,
    mean_diameter: float,
    active_coils: float,
    free_length: float,
    rate: float,
    initial_tension: float = 0.0,
    grade: int = DEFAULT_GRADE,
) -> GradeBox:
    r"""The tolerance box of a coil's law under ``grade`` (SI inputs: m, m, 1, m, N/m, N).

    The law is ``F = F_i + k (L − L0)`` (extension) or ``F = −k (L0 − L)`` (compression). The box is
    ``k (1 ± 1.5 % Q)`` and the constant part ``α_F k_F Q`` of ``A_F``: on the initial tension of an
    extension spring (with its own proportional part, ``± A_F(F_i)``), on the free length of a
    compression spring (``± A_L0``). The largest force deviation over the box at any length is then
    ``A_F(F)`` at that length, the standard's tolerance.
    """
    Q = quality_factor(grade)
    d, D, n = wire_diameter, mean_diameter, active_coils
    constant = alpha_f(d, D) * k_f(n) * Q  # [N]
    dimension = free_length_tolerance(kind, d, D, n, free_length, rate, grade)
    if kind == "extension":
        tension, length = constant + PROPORTIONAL_FORCE * abs(initial_tension) * Q, 0.0
    else:
        tension, length = 0.0, constant / rate
    return GradeBox(
        grade=int(grade),
        rate=PROPORTIONAL_FORCE * Q,
        initial_tension=tension,
        free_length=length,
        coil_diameter=coil_diameter_tolerance(d, D, grade),
        free_length_dimension=dimension,
    )


def relative_force_tolerance(force_tolerance_n: float, force: float) -> float:
    """``A_F / |F|`` [1] (inf at zero force): the force tolerance as a fraction, for reports."""
    return force_tolerance_n / abs(force) if force else math.inf
