"""The standard stock catalogues MS24585 and MS24586: their parts against the standards' table values
(as transcribed by ODOP, in inches and pounds-force), how they are named, and one-line errors."""

from __future__ import annotations

import math
import runpy
from pathlib import Path

import pytest
import yaml

import springbalance as sb
from springbalance.cli import main
from springbalance.io.catalogue import read_catalogue
from springbalance.io.config import config_from_dict
from springbalance.io.stock_catalogues import STANDARD_CATALOGUES, load_stock, standard_catalogue_path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "ms_catalogues" / "make_ms_catalogues.py"
INCH = 0.0254  # [m] per inch (exact)
LBF = 4.4482216152605  # [N] per pound-force (exact)
PSI = LBF / INCH**2  # [Pa] per psi
#: the project's shear moduli (Shigley Table 10-5: music wire 11.75 Mpsi, 302 stainless 10.0 Mpsi)
G = {"music_wire": 81.0e9, "stainless_302": 69.0e9}  # [Pa]

# Rows of the standards' tables as ODOP's copy gives them (tools/ms_catalogues/odop/*.json):
# (part, outer diameter [in], wire [in], free length [in], total coils, material)
MS24585_ROWS = [
    ("MS24585-1", 0.120, 0.016, 0.250, 6.5, "music_wire"),
    ("MS24585-57", 0.180, 0.026, 0.250, 5.25, "music_wire"),  # ODOP's copy names it "56" (a repeat)
    ("MS24585-263", 0.360, 0.042, 0.880, 7.75, "music_wire"),  # ODOP: "283" (a repeat)
    ("MS24585-527", 0.850, 0.067, 1.500, 5.4, "music_wire"),
    ("MS24585C527", 0.850, 0.067, 1.500, 5.4, "stainless_302"),
]
# (part, outer diameter [in], wire [in], total coils, initial tension [lbf], material)
MS24586_ROWS = [
    ("MS24586-1", 0.12, 0.016, 50.5, 0.2, "music_wire"),
    ("MS24586C1", 0.12, 0.016, 50.5, 0.17, "stainless_302"),
    ("MS24586-221", 0.65, 0.055, 24.5, 0.9, "music_wire"),
    ("MS24586-353", 1.0, 0.095, 32.0, 2.7, "music_wire"),  # ODOP's copy names it "352" (a repeat)
    ("MS24586C354", 1.0, 0.095, 34.5, 2.25, "stainless_302"),
]


@pytest.fixture(scope="module")
def catalogues():
    return {name: {part.part_number: part for part in load_stock(name)} for name in STANDARD_CATALOGUES}


def rate_n_per_m(material, d_in, D_in, n):
    """``G d⁴/(8 D³ n)`` in lbf/in (G in psi), converted to N/m."""
    return G[material] / PSI * d_in**4 / (8 * D_in**3 * n) * LBF / INCH


# ---------------------------------------------------------------------- the parts
@pytest.mark.parametrize("row", MS24585_ROWS, ids=lambda row: row[0])
def test_ms24585_parts_are_the_standards_rows_in_si(catalogues, row):
    number, od, d, free, total, material = row
    part = catalogues["ms24585"][number]
    D = od - d  # mean diameter [in]
    active = total - 2  # closed and ground ends: one inactive coil at each end
    assert part.kind == "compression" and part.material == material
    assert part.wire_diameter == pytest.approx(d * INCH, rel=1e-9)
    assert part.mean_diameter == pytest.approx(D * INCH, rel=1e-9)
    assert part.active_coils == pytest.approx(active)
    assert part.free_length == part.max_length == pytest.approx(free * INCH, rel=1e-9)
    assert part.min_length == pytest.approx(d * total * INCH, rel=1e-9)  # solid length of ground ends
    assert part.initial_tension == 0
    assert part.rate == pytest.approx(rate_n_per_m(material, d, D, active), rel=1e-9)
    # the largest load: the body stress at its allowable (Shigley Table 10-6, Eq. 10-6), or solid
    strength = {"music_wire": 2211e6 / (d * 25.4) ** 0.145, "stainless_302": 1867e6 / (d * 25.4) ** 0.146}[material]
    fraction = {"music_wire": 0.45, "stainless_302": 0.35}[material]
    C = D / d
    at_stress = fraction * strength * math.pi * (d * INCH) ** 3 / (8 * (4 * C + 2) / (4 * C - 3) * D * INCH)
    at_solid = part.rate * (free - d * total) * INCH
    assert part.max_load == pytest.approx(min(at_stress, at_solid), rel=1e-9)


@pytest.mark.parametrize("row", MS24586_ROWS, ids=lambda row: row[0])
def test_ms24586_parts_are_the_standards_rows_in_si(catalogues, row):
    number, od, d, total, tension, material = row
    part = catalogues["ms24586"][number]
    D = od - d
    assert part.kind == "extension" and part.material == material
    assert part.wire_diameter == pytest.approx(d * INCH, rel=1e-9)
    assert part.mean_diameter == pytest.approx(D * INCH, rel=1e-9)
    assert part.active_coils == pytest.approx(total)
    # free length inside the full hooks: two inside diameters plus the close-wound body d (n + 1)
    assert part.free_length == part.min_length == pytest.approx((2 * (od - 2 * d) + d * (total + 1)) * INCH, rel=1e-9)
    assert part.initial_tension == pytest.approx(tension * LBF, rel=1e-9)
    assert part.rate == pytest.approx(rate_n_per_m(material, d, D, total), rel=1e-9)
    assert part.max_length == pytest.approx(part.free_length + (part.max_load - part.initial_tension) / part.rate)
    assert part.initial_tension < part.max_load


def test_ms24586_first_part_is_one_inch_long_and_the_largest_load_is_the_weakest_rule(catalogues):
    # MS24586-1: 2 × (0.120 − 2 × 0.016) + 0.016 × 51.5 = 1.000 in between the hooks
    part = catalogues["ms24586"]["MS24586-1"]
    assert part.free_length == pytest.approx(1.000 * INCH, rel=1e-9)
    # its largest load, from Shigley: body K_B 8FD/(πd³) ≤ 0.45 S_ut, hook bending (Eq. 10-34, C1 = D/d)
    # ≤ 0.75 S_ut, hook torsion ((K)_B = 1.25 at C2 = 4) ≤ 0.40 S_ut; S_ut = 2211 MPa/d[mm]^0.145
    d, D = 0.016 * INCH, 0.104 * INCH
    C = D / d
    strength = 2211e6 / (d * 1e3) ** 0.145
    unit = 8 * D / (math.pi * d**3)  # [Pa/N]
    body = 0.45 * strength / ((4 * C + 2) / (4 * C - 3) * unit)
    bending = (
        0.75 * strength / ((4 * C * C - C - 1) / (4 * C * (C - 1)) * 16 * D / (math.pi * d**3) + 4 / (math.pi * d**2))
    )
    torsion = 0.40 * strength / (1.25 * unit)
    assert part.max_load == pytest.approx(min(body, bending, torsion), rel=1e-9)


def test_both_catalogues_hold_every_dash_number_once(catalogues):
    for name, count, kind in (("ms24585", 527, "compression"), ("ms24586", 354, "extension")):
        numbers = set(catalogues[name])
        standard = name.upper()
        assert numbers == {f"{standard}-{i}" for i in range(1, count + 1)} | {
            f"{standard}C{i}" for i in range(1, count + 1)
        }
        assert {part.kind for part in catalogues[name].values()} == {kind}
        assert {part.material for part in catalogues[name].values()} == {"music_wire", "stainless_302"}


def test_the_packaged_files_are_what_the_script_writes_and_carry_the_licence(tmp_path):
    script = runpy.run_path(str(SCRIPT))
    for name in STANDARD_CATALOGUES:
        shipped = standard_catalogue_path(name)
        assert shipped.read_text(encoding="utf-8") == script["catalogue_text"](name.upper())
        assert "ODOP" in shipped.read_text(encoding="utf-8").splitlines()[1]
    folder = standard_catalogue_path("ms24585").parent
    assert "MIT License" in (folder / "LICENSE-ODOP.txt").read_text(encoding="utf-8")
    assert script["ODOP_COMMIT"] in (folder / "README.md").read_text(encoding="utf-8")


# ---------------------------------------------------------------------- names, paths and errors
def test_a_spec_names_catalogues_or_files_any_case_comma_separated(tmp_path):
    compression, extension = load_stock("ms24585"), load_stock("MS24586")
    both = load_stock(" ms24585 , ms24586 ")
    assert [p.part_number for p in both] == [p.part_number for p in compression + extension]
    assert len(load_stock(["ms24586", "ms24586"])) == len(extension)  # named twice, read once
    path = tmp_path / "mine.csv"
    path.write_text(standard_catalogue_path("ms24586").read_text(encoding="utf-8").replace("MS24586", "MINE"))
    mine = load_stock(f"ms24585,{path}")
    assert len(mine) == len(compression) + len(extension) and mine[-1].part_number.startswith("MINE")
    assert len(load_stock("mine.csv", base_dir=tmp_path)) == len(extension)
    assert sb.load_stock is load_stock


@pytest.mark.parametrize(
    "spec, message",
    [
        ("ms2458", "unknown stock catalogue 'ms2458': not a standard catalogue (ms24585, ms24586) and no such file"),
        ("ms24585,", "stock catalogue 'ms24585,': expected a catalogue name"),
        ("", "stock catalogue '': expected a catalogue name"),
        ("missing.csv", "stock catalogue 'missing.csv' does not exist"),
    ],
)
def test_bad_specs_one_line_error(spec, message):
    with pytest.raises(sb.InputError) as error:
        load_stock(spec)
    assert str(error.value).startswith(message) and "\n" not in str(error.value)


def test_a_part_in_two_catalogues_is_an_error(tmp_path):
    copy = tmp_path / "copy.csv"
    copy.write_text(standard_catalogue_path("ms24586").read_text(encoding="utf-8"))
    with pytest.raises(sb.InputError, match=rf"stock catalogues ms24586 and {copy} both hold part 'MS24586-1'"):
        load_stock(f"ms24586,{copy}")


def test_cli_rejects_a_bad_stock_name_in_one_line(tmp_path, capsys):
    config = tmp_path / "c.yaml"
    config.write_text("mechanism: {urdf: x.urdf}\n")  # never read: the stock spec fails first
    assert main(["design", str(config), "--stock", "ms2458", "--out", str(tmp_path / "d.json")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "unknown stock catalogue 'ms2458'" in err


def lamp_config(stock):
    return {
        "mechanism": {"urdf": str(ROOT / "urdf" / "desk_lamp.urdf")},
        "workspace": {"kind": "grid", "n": 8},
        "springs": [
            {
                "name": "lift",
                "type": "extension",
                "a": {"body": "ground", "box": {"lower": [0, -0.02, 0.02], "upper": [0, 0.02, 0.15]}},
                "b": {"body": "arm", "box": {"lower": [0, 0, 0.01], "upper": [0, 0, 0.15]}},
            }
        ],
        "solve": {"stock": stock},
    }


def test_config_solve_stock_names_the_parts(tmp_path):
    config = config_from_dict(lamp_config(["ms24586", "ms24585"]), base_dir=tmp_path)
    assert config.stock_source == "ms24586,ms24585" and "stock" not in config.solve_options
    assert len(config.stock) == 708 + 1054
    with pytest.raises(sb.ConfigError) as error:
        config_from_dict(lamp_config("ms2458"), label="lamp.yaml")
    assert str(error.value).startswith("lamp.yaml: solve.stock: unknown stock catalogue 'ms2458'")
    with pytest.raises(sb.ConfigError, match=r"solve\.stock"):
        config_from_dict(lamp_config(3), label="lamp.yaml")
    example = yaml.safe_load((ROOT / "examples" / "desk_lamp.yaml").read_text())
    assert example["solve"]["stock"] == "ms24586"


def test_read_catalogue_reads_the_packaged_files():
    assert len(read_catalogue(standard_catalogue_path("ms24585"))) == 1054
