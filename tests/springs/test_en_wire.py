"""EN 10270-1 SH/DH spring wire (docs/model.md §3.8.1): the strength fit against the standard's values."""

from __future__ import annotations

import math

import pytest

from springbalance.springs.materials import MATERIALS

#: Rm,min [MPa] of grades SH and DH at the upper diameter [mm] of each row of EN 10270-1 Table 3, as
#: reproduced by Hengming Steel Wire (rows 0.20–0.34 mm) and Durofer (0.35, 0.40, 0.45 mm).
SH_AND_DH = {0.30: 2660, 0.32: 2640, 0.34: 2610, 0.35: 2600, 0.40: 2560, 0.45: 2510}
#: rows listed for DH only (EN 10270-1 has no SH wire below 0.30 mm), same source
DH_ONLY = {0.20: 2800, 0.22: 2770, 0.25: 2720, 0.28: 2680}


def _strength(name: str, diameter_mm: float) -> float:
    return float(MATERIALS[name].tensile_strength(diameter_mm * 1e-3)) / 1e6  # [MPa]


@pytest.mark.parametrize("name", ["en10270_1_sh", "en10270_1_dh"])
def test_the_fit_stays_within_1_2_percent_below_the_table(name: str) -> None:
    rows = {**SH_AND_DH, **(DH_ONLY if name.endswith("dh") else {})}
    for diameter, minimum in rows.items():
        fit = _strength(name, diameter)
        assert -0.012 * minimum <= fit - minimum <= 0.0, (diameter, fit, minimum)


@pytest.mark.parametrize("diameter", [0.5, 0.8, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0, 10.0])
def test_the_fit_stays_within_2_7_percent_below_the_reference_line_above_half_a_millimetre(diameter: float) -> None:
    # SpringONE's EN 10270-1 SH minimum line, Rm = 2220 − 820 log10(d/mm) MPa (0.28–20 mm)
    reference = 2220.0 - 820.0 * math.log10(diameter)
    for name in ("en10270_1_sh", "en10270_1_dh"):
        fit = _strength(name, diameter)
        assert -0.027 * reference <= fit - reference <= 0.0, (name, diameter, fit, reference)


def test_moduli_density_ranges_and_allowables() -> None:
    for name, thinnest in (("en10270_1_sh", 0.30e-3), ("en10270_1_dh", 0.20e-3)):
        material = MATERIALS[name]
        assert material.shear_modulus == pytest.approx(81.5e9)  # EN 13906-1
        assert material.density == pytest.approx(7850.0)  # EN 10270-1: 7.85 kg/dm³
        assert material.diameter_range == pytest.approx((thinnest, 10e-3))
        # Shigley Tables 10-6, 10-7: cold-drawn carbon steel
        assert material.allowable_fraction == {"compression": 0.45, "extension": 0.45}
        assert material.hook_fraction == {"bending": 0.75, "torsion": 0.40}
