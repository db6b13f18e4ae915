"""The springs' mass against the floor and the arm, and the bound max_spring_mass (docs/model.md §5.1).

The hand-computable case is the single link R1 (urdf/single_link_r1.urdf, docs/model.md §10): a link of
m = 8 kg with its centre of mass c = 0.183 m from the pivot, the joint angle phi from the upward
vertical over its URDF range [120°, 180°]. Its gravity potential is V_g = m g c cos(phi), so over a grid
that holds both ends it swings by m g c (cos 120° − cos 180°) = m g c / 2. The energy a coil stores
per kilogram is derived here from the rate and the stress of a helical spring (Shigley ch. 10), not
from the code's formula: a coil of wire d, mean diameter D and n active coils has rate
k = G d⁴/(8 D³ n) and corrected stress K_B 8 F D/(π d³); at the allowable stress it holds F²/(2k),
and its wire weighs ρ (π d²/4) π D (n + 2).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.spring_mass import check_mass_bound, fatigue_energy_fraction
from springbalance.errors import InputError
from springbalance.io.config import config_from_dict, load_config
from springbalance.springs.fatigue import Duty
from springbalance.springs.materials import material_named

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf"
M, C, G = 8.0, 0.183, 9.81  # link mass [kg], centre of mass [m], gravity [m/s²]
SWING = M * G * C * (math.cos(2 * math.pi / 3) - math.cos(math.pi))  # ΔV of the link [J]
# music wire (Shigley Tables 10-4, 10-5, 10-6, A-5): S_ut = 2211 MPa / d[mm]^0.145, 45 % allowable
MUSIC_G, MUSIC_RHO, MUSIC_A, MUSIC_M, MUSIC_F = 81.0e9, 7800.0, 2211e6, 0.145, 0.45


@pytest.fixture(scope="module")
def link():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    return mechanism, sb.Workspace.grid(mechanism, 31)


def _stored_per_kg(d: float, D: float, n: float) -> float:
    """Energy per kilogram [J/kg] of a music-wire coil (d, D [m], n active coils) at its allowable stress,
    from its rate and its Bergsträsser-corrected stress: F²/(2k) over its mass."""
    index = D / d
    bergstrasser = (4 * index + 2) / (4 * index - 3)
    allowable = MUSIC_F * MUSIC_A / (d * 1e3) ** MUSIC_M  # [Pa]
    force = allowable / bergstrasser * math.pi * d**3 / (8 * D)  # the largest force [N]
    rate = MUSIC_G * d**4 / (8 * D**3 * n)  # [N/m]
    mass = MUSIC_RHO * math.pi * d**2 / 4 * math.pi * D * (n + 2)  # [kg]
    return force**2 / (2 * rate) / mass


def _coil(name: str = "c", **parameters) -> sb.HelicalExtensionSpring:
    return sb.HelicalExtensionSpring(
        sb.Anchor("universe", (0, 0, 0.16)), sb.Anchor("link1", (0, 0, 0.3)), name, **parameters
    )


def test_floor_of_a_single_link_from_its_swing_and_the_wire(link):
    mechanism, workspace = link
    # the thinnest wire 1 mm, the index up to 12 (the mean diameter may reach 78 mm) and up to 200 coils
    coil = _coil(wire_diameter=sb.Free(1e-3, 3e-3), initial_tension=10.0)
    problem = sb.DesignProblem(mechanism, workspace, [coil])
    x = np.array(problem.variables.start)
    record = sb.DesignResult(problem, x).spring_mass()
    best = _stored_per_kg(1e-3, 12e-3, 200.0)
    assert record.energy_swing == pytest.approx(SWING, rel=1e-12)  # 7.181 J
    assert record.energy_per_kg == pytest.approx(best, rel=1e-12)
    assert record.floor == pytest.approx(SWING / best, rel=1e-12)
    assert record.floor_material == "music_wire"
    assert record.arm_moving_mass == pytest.approx(M)
    # the thinnest music wire, 0.10 mm, stores 612 J/kg (docs/model.md §5.1)
    thinnest = sb.DesignProblem(mechanism, workspace, [_coil(initial_tension=10.0)])
    record = sb.DesignResult(thinnest, np.array(thinnest.variables.start)).spring_mass()
    assert record.energy_per_kg == pytest.approx(_stored_per_kg(1e-4, 1.2e-3, 200.0), rel=1e-12)
    assert record.energy_per_kg == pytest.approx(612.5, abs=0.1)
    assert record.floor == pytest.approx(SWING / 612.53, rel=1e-4)


def test_each_springs_part_mass_and_the_ratios(link):
    mechanism, workspace = link
    d, D, n = 2e-3, 16e-3, 40.0
    wire = MUSIC_RHO * math.pi * d**2 / 4 * math.pi * D * (n + 2)  # [kg]
    springs = [
        _coil("coil", wire_diameter=d, mean_diameter=D, active_coils=n, initial_tension=20.0),
        _coil("weightless", wire_diameter=d, mean_diameter=D, active_coils=n, initial_tension=20.0, own_mass=False),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0, 0, 0.2)), "given", stiffness=10.0, mass=0.3
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0, 0, 0.2)), "ideal", stiffness=10.0
        ),
    ]
    record = sb.DesignResult(sb.DesignProblem(mechanism, workspace, springs), np.zeros(0)).spring_mass()
    # a coil counts its wire even when the model leaves its weight out; an ideal spring its given mass or 0
    assert record.springs == pytest.approx({"coil": wire, "weightless": wire, "given": 0.3, "ideal": 0.0}, rel=1e-12)
    assert record.total == pytest.approx(2 * wire + 0.3, rel=1e-12)
    assert record.ratio_to_arm == pytest.approx((2 * wire + 0.3) / M, rel=1e-12)
    # fixed coils: their own wire, index and coils set the energy per kilogram
    assert record.ratio_to_floor == pytest.approx((2 * wire + 0.3) / (SWING / _stored_per_kg(d, D, n)), rel=1e-12)


def test_report_html_and_design_json_carry_the_record(link, tmp_path):
    mechanism, workspace = link
    d, D, n = 2e-3, 16e-3, 40.0
    wire = MUSIC_RHO * math.pi * d**2 / 4 * math.pi * D * (n + 2)
    coil = _coil(wire_diameter=d, mean_diameter=D, active_coils=n, initial_tension=20.0)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [coil], max_spring_mass=0.5), np.zeros(0))
    table = result.table()
    assert f"spring mass {wire:.4g} kg (c {wire:.4g} kg); max_spring_mass 0.5 kg" in table
    assert f"{100 * wire / M:.3g} % of the arm's moving mass 8 kg" in table
    page = result.report(tmp_path / "report", scene=False).read_text()
    assert '<p id="spring-mass">Spring mass' in page and "max_spring_mass 0.5 kg" in page
    saved = json.loads(result.save(tmp_path / "design.json").read_text())
    record = saved["spring_mass"]
    assert record["total_kg"] == pytest.approx(wire, rel=1e-12)
    assert record["floor_kg"] == pytest.approx(SWING / _stored_per_kg(d, D, n), rel=1e-12)
    assert record["ratio_to_floor"] == pytest.approx(record["total_kg"] / record["floor_kg"], rel=1e-12)
    assert record["arm_moving_mass_kg"] == pytest.approx(M)
    assert record["max_spring_mass_kg"] == 0.5 and saved["max_spring_mass"] == 0.5
    loaded = sb.DesignResult.load(tmp_path / "design.json")
    assert loaded.problem.max_spring_mass == 0.5
    # a damaged bound in a saved design is named
    saved["max_spring_mass"] = -1
    (tmp_path / "bad.json").write_text(json.dumps(saved))
    with pytest.raises(InputError, match="max_spring_mass: expected a finite number > 0"):
        sb.DesignResult.load(tmp_path / "bad.json")


# ---------------------------------------------------------------------- the bound
def test_the_bound_is_one_row_of_the_nlp(link):
    mechanism, workspace = link
    coil = _coil(initial_tension=10.0)
    free = sb.DesignProblem(mechanism, workspace, [coil])
    bounded = sb.DesignProblem(mechanism, workspace, [coil], max_spring_mass=0.2)
    block = bounded.model.constraint_blocks[-1]
    assert (block.spring, block.name, block.unit, block.per_sample) == ("", "max_spring_mass", "kg", False)
    assert bounded.build().n_rows == free.build().n_rows + 1  # once, not once per sample
    x = np.array(bounded.variables.start)
    values = dict(zip(bounded.variables.names, x))
    d, D, n = values["c.wire_diameter"], values["c.mean_diameter"], values["c.active_coils"]
    wire = MUSIC_RHO * math.pi * d**2 / 4 * math.pi * D * (n + 2)
    rows = bounded.evaluate(x).constraint_rows
    np.testing.assert_allclose(rows[:, block.offset], 0.2 - wire, rtol=1e-12)


@pytest.mark.parametrize("value", [-1.0, 0.0, "1.5", True, float("nan"), float("inf")])
def test_a_bad_bound_names_the_key(link, value):
    mechanism, workspace = link
    with pytest.raises(InputError, match="max_spring_mass must be"):
        sb.DesignProblem(mechanism, workspace, [_coil(initial_tension=10.0)], max_spring_mass=value)


def _config(**extra) -> dict:
    return {
        "mechanism": {"urdf": str(URDF / "single_link_r1.urdf")},
        "workspace": {"kind": "grid", "n": 7},
        "springs": [
            {
                "name": "c",
                "type": "extension",
                "a": {"body": "universe", "point": [0, 0, 0.16]},
                "b": {"body": "link1", "point": [0, 0, 0.3]},
                "wire_diameter": {"lower": 0.002, "upper": 0.004},
                "mean_diameter": {"lower": 0.016, "upper": 0.03},
                "active_coils": {"lower": 10, "upper": 100},
            }
        ],
        **extra,
    }


@pytest.mark.parametrize("value", [-0.5, 0, "heavy", [1.0], True])
def test_a_bad_config_value_names_the_key(value):
    with pytest.raises(sb.ConfigError, match=r"^config: max_spring_mass: expected a number > 0 \[kg\]"):
        config_from_dict(_config(max_spring_mass=value))


def test_a_bound_below_the_lightest_coil_is_refused_before_solving():
    config = config_from_dict(_config(max_spring_mass=1.0))
    assert config.problem.max_spring_mass == 1.0
    # the lightest coil the bounds allow: d 2 mm, D 16 mm, 10 active coils
    lightest = MUSIC_RHO * math.pi * 0.002**2 / 4 * math.pi * 0.016 * 12
    with pytest.raises(
        sb.ConfigError, match=rf"max_spring_mass 0.01 kg is below the lightest springs .* {lightest:.4g} kg"
    ):
        config_from_dict(_config(max_spring_mass=0.01))
    # the same check from Python, on a problem built directly
    problem = config.problem.with_springs(config.problem.springs, max_spring_mass=0.9 * lightest)
    with pytest.raises(InputError, match="below the lightest springs"):
        check_mass_bound(problem)


@pytest.mark.slow
def test_a_tight_bound_holds_after_a_solve_and_costs_balance():
    """examples/two_link.yaml (make demo) with its springs bounded to 0.6 kg in all (the design without a bound
    weighs about 1.3 kg)."""
    config = load_config(ROOT / "examples" / "two_link.yaml")
    free = config.solve()
    bounded_problem = config.problem.with_springs(config.problem.springs, max_spring_mass=0.6)
    bounded = sb.solve(bounded_problem, **config.solve_options)
    assert free.spring_mass().total > 0.6
    assert bounded.spring_mass().total <= 0.6 + 1e-6  # the solver's feasibility tolerance [kg]
    assert bounded.evaluation.max_violation <= 1e-6
    objective = config.problem.objective_value
    assert objective(bounded.evaluation) > objective(free.evaluation)


@pytest.mark.parametrize(
    ("cycles", "amplitude_point"),
    [
        # Zimmerli's infinite-life point (Shigley Eq. 10-28): S_sa = 241 MPa, S_sm = 379 MPa, unpeened
        (math.inf, (241e6, 379e6)),
        # 10⁶ cycles: Table 10-8's body torsion 33 % of S_ut at a stress ratio of 0: S_a = S_m = 0.165 S_ut
        (1e6, None),
    ],
)
def test_a_coil_with_a_duty_exchanges_the_goodman_optimum_share_of_its_energy(cycles, amplitude_point):
    """Goodman: τ_a/S_e + τ_m/S_su = 1/n with S_e = S_a/(1 − S_m/S_su). The energy a coil exchanges between its
    force extremes is ∝ F_max² − F_min² ∝ (τ_m + τ_a)² − (τ_m − τ_a)² = 4 τ_m τ_a, largest at τ_a = S_e/(2n),
    τ_m = S_su/(2n); against the static energy ∝ τ_allow² (from zero to the allowable) that is
    S_e S_su/(n² τ_allow²). Music wire, d = 3 mm: S_ut = 2211 MPa·mm^0.145 / 3^0.145 (Table 10-4),
    S_su = 0.67 S_ut (Eq. 10-30), τ_allow = 0.45 S_ut for a compression spring (Table 10-6), n = 1.2."""
    strength = 2211e6 / 3**0.145  # [Pa]
    ultimate, allowable, n = 0.67 * strength, 0.45 * strength, 1.2
    amplitude, mean = amplitude_point or (0.165 * strength, 0.165 * strength)
    endurance = amplitude / (1 - mean / ultimate)
    assert (endurance + ultimate) / (2 * n) < allowable  # the optimum is inside the static rule
    expected = endurance * ultimate / (n**2 * allowable**2)
    duty = Duty(cycles=cycles, criterion="goodman", safety_factor=n)
    found = fatigue_energy_fraction(material_named("music_wire"), "compression", 0.003, 8.0, duty)
    assert found == pytest.approx(expected, rel=1e-6)
