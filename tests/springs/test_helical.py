"""Helical coil springs (springs/laws/helical_extension.py, helical_compression.py; docs/model.md §3.8).

Every expected value is computed here from Shigley's formulas and constants (Mechanical Engineering
Design, ch. 10), not read from the code: music wire G = 81.0 GPa, ρ = 7800 kg/m³,
S_ut = 2211 MPa·mm^0.145 / d^0.145, body allowable 45 % of S_ut, hooks 75 % (bending) and 40 %
(torsion); Bergsträsser K_B = (4C + 2)/(4C − 3); k = G d⁴/(8 D³ n); extension free length
d (n + 1) + 2 (D − d); initial stress band 231 e^(−0.105 C) ± 6.9 (4 − (C − 3)/6.5) MPa.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from flag_helpers import overloaded_coil
from springbalance.cli import main
from springbalance.io.config import load_config
from springbalance.springs import SPRING_TYPES, spring_from_dict
from springbalance.springs.laws.helical_compression import HelicalCompressionSpring
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
from springbalance.springs.sizing import PREFERRED_WIRE_DIAMETERS

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf"
G_MUSIC, RHO_MUSIC = 81.0e9, 7800.0


def strength(d):
    """Music wire S_ut [Pa] at wire diameter d [m] (Shigley Table 10-4)."""
    return 2211e6 / (d * 1e3) ** 0.145


def bergstrasser(c):
    return (4 * c + 2) / (4 * c - 3)


def check_extension_sheet(sheet: dict) -> list[str]:
    """The must-hold rules of a helical extension spring, checked from its spec sheet alone."""
    d, D, n = sheet["wire_diameter"], sheet["mean_diameter"], sheet["active_coils"]
    failures = []
    rate = G_MUSIC * d**4 / (8 * D**3 * n)
    if abs(rate - sheet["rate"]) > 0.01 * rate:
        failures.append(f"rate {sheet['rate']} vs formula {rate}")
    stress = bergstrasser(D / d) * 8 * sheet["max_load"] * D / (math.pi * d**3)
    if stress > 0.45 * strength(d) * (1 + 1e-4):
        failures.append(f"stress {stress / 1e6:.0f} MPa > allowable {0.45 * strength(d) / 1e6:.0f} MPa")
    if sheet["free_length"] < d * (n + 1) + 2 * (D - d) - 1e-9:
        failures.append("free length shorter than body + hooks")
    if not 4 - 1e-6 <= D / d <= 12 + 1e-6:
        failures.append(f"index {D / d}")
    if sheet["longest_length"] > sheet["free_length"] and sheet["max_load"] < sheet["initial_tension"]:
        failures.append("largest load below the initial tension")
    return failures


def test_type_extension_is_a_coil_unless_ideal():
    assert SPRING_TYPES["extension"] is HelicalExtensionSpring
    assert SPRING_TYPES["compression"] is HelicalCompressionSpring
    ends = {"a": {"body": "universe", "point": [0, 0, 0.1]}, "b": {"body": "link1", "point": [0.3, 0, 0]}}
    assert type(spring_from_dict({"type": "extension", **ends})) is HelicalExtensionSpring
    assert type(spring_from_dict({**ends})) is HelicalExtensionSpring  # the default type
    ideal = spring_from_dict({"type": "extension", "ideal": True, **ends, "stiffness": 100.0, "free_length": 0.1})
    assert type(ideal) is sb.ExtensionSpring and ideal.to_dict()["ideal"] is True
    with pytest.raises(sb.InputError, match="no ideal variant"):
        spring_from_dict({"type": "zero_free_length", "ideal": True, **ends, "stiffness": 1.0})
    with pytest.raises(sb.InputError, match="unknown key 'stiffness'"):
        spring_from_dict({"type": "extension", **ends, "stiffness": 100.0})


def test_extension_coil_law_and_spec_sheet_from_shigley():
    d, D, n, initial = 2.0e-3, 16.0e-3, 20.0, 20.0  # [m], [m], [1], [N]
    spring = HelicalExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.1]),
        sb.Anchor("link1", [0.3, 0, 0]),
        "e",
        wire_diameter=d,
        mean_diameter=D,
        active_coils=n,
        initial_tension=initial,
    )
    values = {"wire_diameter": d, "mean_diameter": D, "active_coils": n, "initial_tension": initial}
    rate = G_MUSIC * d**4 / (8 * D**3 * n)  # 1977 N/m
    free = d * (n + 1) + 2 * (D - d)  # 70 mm
    lengths = np.linspace(free, free + 0.03, 9)  # up to 79 N
    np.testing.assert_allclose(spring.tension(lengths, values), initial + rate * (lengths - free), rtol=1e-12)
    step = 1e-7
    derivative = (spring.potential(lengths + step, values) - spring.potential(lengths - step, values)) / (2 * step)
    np.testing.assert_allclose(derivative, spring.tension(lengths, values), rtol=1e-6)
    sheet = spring.spec_sheet(values, lengths, spring.tension(lengths, values))
    largest = initial + rate * 0.03
    assert sheet["rate"] == pytest.approx(rate, rel=1e-12)
    assert sheet["free_length"] == pytest.approx(free, rel=1e-12)
    assert sheet["body_length"] == pytest.approx(d * (n + 1), rel=1e-12)
    assert sheet["max_stress"] == pytest.approx(bergstrasser(8) * 8 * largest * D / (math.pi * d**3), rel=1e-9)
    assert sheet["allowable_stress"] == pytest.approx(0.45 * strength(d), rel=1e-9)
    assert sheet["mass"] == pytest.approx(RHO_MUSIC * math.pi * d**2 / 4 * math.pi * D * (n + 2), rel=1e-12)
    c = D / d
    band = 231e6 * math.exp(-0.105 * c), 6.9e6 * (4 - (c - 3) / 6.5)
    initial_stress = 8 * initial * D / (math.pi * d**3)  # 102 MPa, inside 99 ± 22 MPa
    assert abs(initial_stress - band[0]) < band[1]
    assert sheet["buildable"], sheet["reasons"]
    assert check_extension_sheet(sheet) == []
    # the same coil stretched eight times further (514 N) is overloaded, and the verdict names why
    long = np.linspace(free, free + 0.25, 9)
    sheet = spring.spec_sheet(values, long, spring.tension(long, values))
    assert not sheet["buildable"]
    assert any("body stress" in reason for reason in sheet["reasons"])
    assert any("hook bending" in reason for reason in sheet["reasons"])


def test_compression_coil_solid_length_and_buckling():
    d, D, n, free = 3.0e-3, 24.0e-3, 10.0, 0.1  # [m], [m], [1], [m]
    spring = HelicalCompressionSpring(
        sb.Anchor("universe", [0, 0, -0.1]),
        sb.Anchor("link1", [0.2, 0, 0]),
        "c",
        wire_diameter=d,
        mean_diameter=D,
        active_coils=n,
        free_length=free,
    )
    values = {"wire_diameter": d, "mean_diameter": D, "active_coils": n, "free_length": free}
    rate = G_MUSIC * d**4 / (8 * D**3 * n)
    lengths = np.linspace(0.05, 0.09, 5)
    np.testing.assert_allclose(spring.tension(lengths, values), -rate * (free - lengths), rtol=1e-12)
    sheet = spring.spec_sheet(values, lengths, spring.tension(lengths, values))
    assert sheet["solid_length"] == pytest.approx(d * (n + 2))  # 36 mm, below the shortest 50 mm
    assert sheet["buckling_length"] == pytest.approx(2.63 * D / 0.5)  # 126 mm > free length
    assert sheet["buildable"], sheet["reasons"]
    short = np.linspace(0.03, 0.09, 5)  # closes solid at 36 mm
    sheet = spring.spec_sheet(values, short, spring.tension(short, values))
    assert any("solid length" in reason for reason in sheet["reasons"])
    tall = HelicalCompressionSpring(
        sb.Anchor("universe", [0, 0, -0.1]),
        sb.Anchor("link1", [0.2, 0, 0]),
        "t",
        wire_diameter=d,
        mean_diameter=D,
        active_coils=n,
        free_length=0.2,
    )
    sheet = tall.spec_sheet(
        {**values, "free_length": 0.2}, lengths, tall.tension(lengths, {**values, "free_length": 0.2})
    )
    assert any("buckling" in reason for reason in sheet["reasons"])


def test_coil_mass_matches_r1b():
    """R1b (Arakelian & Ghazaryan 2007): k = 324.5 N/m on a coil of D = 40 mm, n = 80 weighs 0.8 kg.

    The coil's own geometry (wire for that rate, n + 2 coils of wire) gives the same mass within
    the case's 1 % tolerance of 0.81 kg."""
    D, n, k = 0.04, 80.0, 324.5
    d = (8 * D**3 * n * k / G_MUSIC) ** 0.25
    spring = HelicalExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.16]),
        sb.Anchor("link1", [0, 0, 0.3]),
        "r1b",
        wire_diameter=d,
        mean_diameter=D,
        active_coils=n,
        initial_tension=0.0,
    )
    values = {"wire_diameter": d, "mean_diameter": D, "active_coils": n, "initial_tension": 0.0}
    assert spring.rate(values) == pytest.approx(k, rel=1e-12)
    assert spring.coil_mass(values) == pytest.approx(0.81, rel=0.01)


def test_bad_coil_input_names_the_culprit():
    ends = {"a": {"body": "universe", "point": [0, 0, 0.1]}, "b": {"body": "link1", "point": [0.3, 0, 0]}}
    with pytest.raises(sb.InputError, match="unknown spring material 'steel'"):
        spring_from_dict({"name": "s", **ends, "material": "steel"})
    with pytest.raises(sb.InputError, match="max_outer_diameter 0.4 mm is smaller than any coil"):
        spring_from_dict({"name": "s", **ends, "max_outer_diameter": 0.0004})
    with pytest.raises(sb.InputError, match="wire_diameter .* leaves the range"):
        spring_from_dict({"name": "s", **ends, "wire_diameter": {"lower": 0.01, "upper": 0.02}})


def test_unknown_material_in_a_config_exits_2(tmp_path, capsys):
    config = {
        "mechanism": {"urdf": str(URDF / "single_link_r1.urdf")},
        "workspace": {"kind": "grid", "n": 11},
        "springs": [
            {
                "name": "s",
                "a": {"body": "universe", "point": [0, 0, 0.16]},
                "b": {"body": "link1", "point": [0, 0, 0.3]},
                "material": "unobtainium",
            }
        ],
    }
    path = tmp_path / "config.json"
    path.write_text(json.dumps(config))
    assert main(["design", str(path), "--out", str(tmp_path / "design.json"), "--quiet"]) == 2
    error = capsys.readouterr().err
    assert "unobtainium" in error and "Traceback" not in error and len(error.strip().splitlines()) == 1
    assert not (tmp_path / "design.json").exists()


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """`make demo`'s design: examples/two_link.yaml through the command line, saved as design.json."""
    out = tmp_path_factory.mktemp("demo") / "design.json"
    assert main(["design", str(ROOT / "examples" / "two_link.yaml"), "--out", str(out), "--quiet"]) == 0
    return json.loads(out.read_text())


def test_make_demo_design_is_buildable(demo):
    assert [spring["type"] for spring in demo["design"]] == ["extension"] * 3
    for spring in demo["design"]:
        sheet = spring["helical"]
        assert sheet["buildable"], (spring["name"], sheet["reasons"])
        assert check_extension_sheet(sheet) == [], spring["name"]
        for key in (
            "material",
            "wire_diameter",
            "mean_diameter",
            "active_coils",
            "free_length",
            "body_length",
            "initial_tension",
            "max_stress",
            "allowable_stress",
            "buildable",
            "reasons",
        ):
            assert key in sheet
        # standard wire: the preferred series
        assert min(abs(sheet["wire_diameter"] - d) for d in PREFERRED_WIRE_DIAMETERS) < 1e-12, spring["name"]
        assert sheet["outer_diameter"] <= 0.04 * (1 + 1e-6)
        # its duty (10⁶ cycles, n_f ≥ 1.2): fatigue of the body and both hooks is a rule of the design
        assert sheet["duty"]["cycles"] == 1e6 and sheet["duty"]["safety_factor"] == 1.2
        for location in ("body", "hook_bending", "hook_torsion"):
            assert sheet["fatigue"][location]["safety_factor"] >= 1.2 * (1 - 1e-5), (spring["name"], location)
    shoulder = next(row for row in demo["metrics"]["joints"] if row["joint"] == "shoulder")
    # 90 % without fatigue; the forearm coil's duty costs some balance (docs/model.md §3.8.2)
    assert shoulder["rms_reduction_percent"] >= 85
    rounding = demo["solver"]["standard_wire"]
    assert set(rounding["wires"]) == {"shoulder_spring", "forearm_spring", "elbow_spring"}
    assert rounding["objective"] >= rounding["continuous_objective"] * (1 - 1e-6) or rounding["cost_percent"] < 0


def test_helical_config_loads_with_defaults():
    config = load_config(ROOT / "examples" / "two_link.yaml")
    spring = config.springs[0]
    assert isinstance(spring, HelicalExtensionSpring) and spring.material.name == "music_wire"
    names = config.problem.variables.names
    assert "shoulder_spring.wire_diameter" in names and "shoulder_spring.initial_tension" in names


def test_an_overloaded_coil_is_flagged_in_every_report(tmp_path):
    """A fixed coil stretched far beyond its allowable load: the `unbuildable` warning names the rules."""
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 31, ranges={"pivot": (2 * np.pi / 3, np.pi)})
    # 1 mm wire, D = 8 mm, 10 coils: k = 81e9 · 1e-12 / (8 · 5.12e-7 · 10) ≈ 1978 N/m, free length 25 mm,
    # stretched to about 0.43 m: ≈ 800 N on a wire whose body allows 45 % · 2211 MPa ≈ 1 GPa at ≈ 20 N
    coil = overloaded_coil()
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [coil]), np.zeros(0))
    assert not result.spring("thin")["helical"]["buildable"]
    kinds = [flag.kind for flag in result.warnings()]
    assert "unbuildable" in kinds
    assert "[unbuildable]" in result.table() and "NOT BUILDABLE" in result.table()
    html = result.report(tmp_path, scene=False).read_text()
    assert "unbuildable" in html and "not buildable" in html
    result.save(tmp_path / "design.json")
    saved = json.loads((tmp_path / "design.json").read_text())
    assert any(flag["kind"] == "unbuildable" and flag["subject"] == "thin" for flag in saved["warnings"])
    assert saved["design"][0]["helical"]["buildable"] is False
