"""The heavy_springs warning (springbalance.results.flags, docs/model.md §5.1) on the single link R1
(urdf/single_link_r1.urdf: 8 kg, centre of mass 0.183 m from the pivot, phi ∈ [120°, 180°]).

The link's gravity potential m g c cos(phi) swings by m g c / 2 = 7.18 J. A spring that balances it exactly
is the zero-free-length spring k* = m g c/(a b) from a = 0.16 m above the pivot to b = 0.3 m along the link
(docs/model.md §9). Without helical coils the floor takes the best listed wire, music wire at 0.10 mm
(S_ut = 2211 MPa / 0.1^0.145, 45 % allowable, index 12, G 81.0 GPa, 7800 kg/m³), so it is 11.6 g.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.results.flags import heavy_springs_flags

URDF = Path(__file__).resolve().parents[2] / "urdf"
M, C, G, A, B = 8.0, 0.183, 9.81, 0.16, 0.3
K_STAR = M * G * C / (A * B)  # [N/m]
SWING = M * G * C / 2  # [J]
TAU = 0.45 * 2211e6 / 0.1**0.145 / (50 / 45)  # uncorrected stress at the allowable, 0.10 mm wire, C = 12 [Pa]
FLOOR = SWING / (TAU**2 / (4 * 81.0e9 * 7800.0))  # [kg]


@pytest.fixture(scope="module")
def link():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    return mechanism, sb.Workspace.grid(mechanism, 31)


def _balanced(link, mass: float | None) -> sb.DesignResult:
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, A)), sb.Anchor("link1", (0, 0, B)), "s1", stiffness=K_STAR, mass=mass
    )
    return sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))


def test_the_floor_without_coils_is_the_best_listed_wire(link):
    record = _balanced(link, 0.02).spring_mass()
    assert record.floor == pytest.approx(FLOOR, rel=1e-12)
    assert FLOOR == pytest.approx(0.0116, abs=1e-4)
    assert record.floor_material == "music_wire"


@pytest.mark.parametrize("mass", [None, 0.02])
def test_light_springs_are_not_flagged(link, mass):
    # 20 g: 0.25 % of the link and 1.7× the floor; no mass at all counts 0
    result = _balanced(link, mass)
    assert heavy_springs_flags(result) == []
    assert "heavy_springs" not in [flag.kind for flag in result.warnings()]


@pytest.mark.parametrize(
    ("mass", "arm", "floor"),
    [
        (1.0, "12.5 %", f"{1.0 / FLOOR:.3g}×"),  # above 10 % of the arm, and above 4× the floor
        (0.06, "0.75 %", f"{0.06 / FLOOR:.3g}×"),  # below 10 % of the arm, above 4× the floor (5.2×)
    ],
)
def test_heavy_springs_are_flagged_with_both_ratios(link, tmp_path, mass, arm, floor):
    result = _balanced(link, mass)
    found = [flag for flag in result.warnings() if flag.kind == "heavy_springs"]
    assert len(found) == 1
    flag = found[0]
    assert flag.subject == "springs"
    assert f"the springs weigh {mass:.4g} kg: {arm} of the arm's moving mass 8 kg" in flag.message
    assert f"{floor} the floor {FLOOR:.3g} kg" in flag.message
    assert "max_spring_mass" in flag.hint
    # in the text report, report.html and design.json
    assert f"[heavy_springs] {flag.message}" in result.table()
    page = result.report(tmp_path / "report", scene=False).read_text()
    assert '<tr class="warning heavy_springs">' in page
    saved = json.loads(result.save(tmp_path / "design.json").read_text())
    assert {
        "kind": "heavy_springs",
        "severity": "warning",
        "subject": "springs",
        "message": flag.message,
        "hint": flag.hint,
    } in saved["warnings"]


def test_just_below_both_thresholds_is_not_flagged(link):
    # 4× the floor is 46 g, 10 % of the arm 0.8 kg: 45 g is below both
    mass = 0.99 * 4 * FLOOR
    assert mass < 0.1 * M and math.isclose(mass / FLOOR, 3.96)
    assert heavy_springs_flags(_balanced(link, mass)) == []
    assert heavy_springs_flags(_balanced(link, 1.01 * 4 * FLOOR)) != []
