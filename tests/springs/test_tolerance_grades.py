"""The quality grades of EN 15800 (compression) and DIN 2097 (extension) against the sources' numbers.

Sources (docs/model.md §3.10):

- the mean-diameter table ``A_D`` as printed by Gutekunst Federn,
  https://blog.federnshop.com/en/tension-spring-tolerances/ (grades 1, 2, 3; index 4–8, 8–14, 14–20);
- the extension springs' free-length table (DIN 2097, grade 2) as printed by industrial-springs.com,
  https://www.industrial-springs.com/faq/extension-springs/what-tolerances-does-an-extension-spring-have;
- the EN 15800 formulas ``α_F``, ``k_F``, ``A_F = (α_F k_F + 1.5 F/100) Q``, ``A_L0 = α_F k_F Q / R``,
  ``Q`` = 0.63 / 1 / 1.6 (EN 15800:2008 §4), evaluated here by hand in mm and N.
"""

from __future__ import annotations

import itertools

import pytest

from springbalance.errors import InputError
from springbalance.springs import tolerance_grades as tg

MM = 1e-3


@pytest.mark.parametrize(
    ("D_mm", "d_mm", "grade", "expected_mm"),
    [
        (12.0, 1.2, 1, 0.20),  # row 10–16 mm, w = 10 (8–14)
        (12.0, 1.2, 2, 0.35),
        (12.0, 1.2, 3, 0.70),
        (20.0, 4.0, 2, 0.35),  # row 16–25 mm, w = 5 (4–8)
        (20.0, 1.25, 2, 0.50),  # row 16–25 mm, w = 16 (14–20)
        (3.0, 0.5, 2, 0.15),  # row 2.5–4 mm, w = 6
        (150.0, 15.0, 3, 4.60),  # row 125–160 mm, w = 10
    ],
)
def test_coil_diameter_table(D_mm, d_mm, grade, expected_mm):
    assert tg.coil_diameter_tolerance(d_mm * MM, D_mm * MM, grade) == pytest.approx(expected_mm * MM)


@pytest.mark.parametrize(
    ("L0_mm", "w", "expected_mm"),
    [(80.0, 6.0, 1.50), (80.0, 10.0, 1.80), (30.0, 5.0, 0.80), (300.0, 12.0, 4.00), (500.0, 6.0, 7.5)],
)
def test_extension_free_length_table_grade_2(L0_mm, w, expected_mm):
    d = 1.0 * MM
    assert tg.free_length_tolerance("extension", d, w * d, 20.0, L0_mm * MM, 1000.0, 2) == pytest.approx(
        expected_mm * MM
    )


def test_en15800_formulas_by_hand():
    # d = 2 mm, D = 20 mm (w = 10, w/10 = 1): the bracket is −0.84 + 3.781 − 4.244 + 2.274 = 0.971
    alpha = 65.92 * 2.0**3.3 / 20.0**1.6 * 0.971  # [N]
    kf = 1 / (3 * 10**2) + 8 / (5 * 10) + 0.803  # n = 10: 0.96633…
    assert tg.alpha_f(2 * MM, 20 * MM) == pytest.approx(alpha, rel=1e-12)
    assert tg.k_f(10) == pytest.approx(0.9663333333, rel=1e-9)
    # A_F at F = 100 N: (α_F k_F + 1.5) Q
    for grade, Q in ((1, 0.63), (2, 1.0), (3, 1.6)):
        assert tg.force_tolerance(2 * MM, 20 * MM, 10, 100.0, grade) == pytest.approx((alpha * kf + 1.5) * Q)
    # A_L0 of a compression spring with R = 4 N/mm = 4000 N/m: α_F k_F Q / R [mm]
    assert tg.free_length_tolerance("compression", 2 * MM, 20 * MM, 10, 0.08, 4000.0, 2) == pytest.approx(
        alpha * kf / 4.0 * MM
    )
    # the bracket at w = 5 (w/10 = 0.5): −0.105 + 0.94525 − 2.122 + 2.274 = 0.99225
    assert tg.alpha_f(2 * MM, 10 * MM) == pytest.approx(65.92 * 2.0**3.3 / 10.0**1.6 * 0.99225, rel=1e-12)


@pytest.mark.parametrize("kind", ["extension", "compression"])
def test_grade_box_reproduces_the_force_tolerance_at_every_length(kind):
    """The worst force over the 8 corners of the law's box equals A_F(F) at each length."""
    d, D, n, k = 2 * MM, 16 * MM, 12.0, 3000.0
    L0, Fi = 0.06, 15.0 if kind == "extension" else 0.0
    box = tg.grade_box(kind, d, D, n, L0, k, Fi, 2)

    def law(rate, tension, free, length):
        return tension + rate * (length - free) if kind == "extension" else -rate * (free - length)

    lengths = [0.07, 0.09, 0.12] if kind == "extension" else [0.03, 0.045, 0.055]
    for length in lengths:
        nominal = law(k, Fi, L0, length)
        worst = max(
            abs(law(k * (1 + a * box.rate), Fi + b * box.initial_tension, L0 + c * box.free_length, length) - nominal)
            for a, b, c in itertools.product((-1, 1), repeat=3)
        )
        # the product term Δk·ΔL0 of a compression spring is second order: 1.5 % of the length term
        assert worst == pytest.approx(
            tg.force_tolerance(d, D, n, nominal, 2), rel=0.02 if kind == "compression" else 1e-12
        )
    assert box.rate == pytest.approx(0.015)


@pytest.mark.parametrize("grade", [0, 4, 2.5, True, "2"])
def test_bad_grade(grade):
    with pytest.raises(InputError, match="grade must be 1, 2 or 3"):
        tg.quality_factor(grade)
