"""Stock catalogues: the example catalogue and how it was made, and one-line errors for bad files."""

from __future__ import annotations

import csv
import math
import runpy
from pathlib import Path

import pytest

from springbalance.cli import main
from springbalance.errors import InputError
from springbalance.io.catalogue import COLUMNS, read_catalogue

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "stock_springs.csv"
SCRIPT = ROOT / "examples" / "make_stock_catalogue.py"

G_MUSIC_WIRE = 81.0e9  # [Pa], Shigley Table 10-5 (music wire, 1.6–3.2 mm)

HEADER = ",".join(COLUMNS)
EXTENSION_ROW = "E1,extension,music_wire,0.002,0.016,20,0.07,10,1977.539,120,0.2,0.07"
COMPRESSION_ROW = "C1,compression,music_wire,0.002,0.016,8,0.0552,0,4943.848,60,0.0552,0.02"


def write(tmp_path: Path, *lines: str, name: str = "parts.csv") -> Path:
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


# ---------------------------------------------------------------------- the example catalogue
def test_example_catalogue_reads_and_every_row_follows_the_coil_formulas():
    parts = read_catalogue(EXAMPLE)
    assert 100 <= len(parts) <= 300
    assert {part.kind for part in parts} == {"extension", "compression"}
    assert len({part.part_number for part in parts}) == len(parts)
    for part in parts:
        d, D, n = part.wire_diameter, part.mean_diameter, part.active_coils
        assert part.material == "music_wire"
        assert 0.8e-3 - 1e-12 <= d <= 4.0e-3 + 1e-12
        assert round(D / d, 9) in (6, 8, 10)
        rate = G_MUSIC_WIRE * d**4 / (8 * D**3 * n)  # Shigley Eq. 10-9, recomputed here
        assert part.rate == pytest.approx(rate, rel=0.01), part.part_number
        if part.kind == "extension":
            assert part.free_length == pytest.approx(2 * (D - d) + d * (n + 1), rel=1e-6), part.part_number
            assert part.min_length == part.free_length
            C = D / d
            middle = 231e6 / math.exp(0.105 * C)  # τ_i [Pa], Shigley Eq. 10-40
            half = 6.9e6 * (4 - (C - 3) / 6.5)
            tau_i = 8 * part.initial_tension * D / (math.pi * d**3)
            assert middle - half < tau_i < middle + half
            assert tau_i == pytest.approx(middle, rel=1e-3)
            assert part.max_length == pytest.approx(
                part.free_length + (part.max_load - part.initial_tension) / part.rate, abs=2e-6
            )
        else:
            assert part.initial_tension == 0
            assert part.min_length == pytest.approx(d * (n + 2), rel=1e-6)  # squared and ground: solid length
            assert part.max_length == part.free_length
            assert part.max_load <= part.rate * (part.free_length - part.min_length) * (1 + 1e-4)  # not beyond solid


def test_example_catalogue_is_what_the_script_makes_and_says_it_is_not_a_vendors():
    script = runpy.run_path(str(SCRIPT))
    assert script["catalogue_text"]() == EXAMPLE.read_text()
    assert "not a vendor" in script["__doc__"].lower()
    assert "not a vendor" in " ".join(EXAMPLE.read_text().splitlines()[:2])


def test_columns_in_any_order_extra_columns_comments_and_blank_lines(tmp_path):
    rows = list(csv.reader([HEADER, EXTENSION_ROW, COMPRESSION_ROW]))
    order = list(reversed(range(len(COLUMNS))))
    lines = ["# a comment", "", ",".join(["price"] + [rows[0][i] for i in order])]
    lines += [",".join(["9.90"] + [row[i] for i in order]) for row in rows[1:]]
    parts = read_catalogue(write(tmp_path, *lines))
    assert [part.part_number for part in parts] == ["E1", "C1"]
    assert parts[0].rate == 1977.539 and parts[0].initial_tension == 10.0
    assert parts[1].kind == "compression" and parts[1].min_length == 0.02


# ---------------------------------------------------------------------- bad catalogues
@pytest.mark.parametrize(
    "lines, expected",
    [
        (
            (HEADER.replace(",rate", "").replace(",max_load", ""), EXTENSION_ROW),
            ["line 1", "missing column(s) rate, max_load"],
        ),
        ((HEADER, EXTENSION_ROW.replace(",1977.539,", ",-1977.539,")), ["line 2", "part 'E1'", "column 'rate'", "> 0"]),
        (
            (HEADER, "# comment", EXTENSION_ROW, COMPRESSION_ROW.replace("music_wire", "unobtainium")),
            ["line 4", "part 'C1'", "column 'material'", "unknown material 'unobtainium'", "music_wire"],
        ),
        ((HEADER, EXTENSION_ROW.replace("extension", "torsion")), ["line 2", "column 'type'", "'torsion'"]),
        ((HEADER, EXTENSION_ROW.replace(",0.07,10,", ",0.07,ten,")), ["line 2", "column 'initial_tension'", "'ten'"]),
        ((HEADER, EXTENSION_ROW.replace(",0.07,10,", ",0.07,nan,")), ["line 2", "column 'initial_tension'", "finite"]),
        ((HEADER, EXTENSION_ROW.replace(",120,", ",0,")), ["line 2", "column 'max_load'", "> 0"]),
        ((HEADER, EXTENSION_ROW.replace(",1977.539,", ",2100,")), ["line 2", "column 'rate'", "G d⁴/(8 D³ n)", "2 %"]),
        ((HEADER, COMPRESSION_ROW.replace(",0,4943", ",5,4943")), ["line 2", "column 'initial_tension'", "must be 0"]),
        ((HEADER, COMPRESSION_ROW.replace(",0.0552,0.02", ",0.0552,0.06")), ["line 2", "column 'min_length'", "solid"]),
        ((HEADER, EXTENSION_ROW, EXTENSION_ROW), ["line 3", "column 'part_number'", "'E1'", "line 2"]),
        ((HEADER, EXTENSION_ROW + ",extra"), ["line 2", "13 cells", "12 columns"]),
        ((HEADER,), ["holds no parts"]),
        (("# only a comment",), ["empty stock catalogue"]),
    ],
)
def test_bad_catalogue_one_line_error_naming_file_line_and_column(tmp_path, lines, expected):
    path = write(tmp_path, *lines)
    with pytest.raises(InputError) as error:
        read_catalogue(path)
    message = str(error.value)
    assert "\n" not in message
    assert message.startswith(str(path))
    for part in expected:
        assert part in message, message


def test_missing_catalogue_file(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        read_catalogue(tmp_path / "nope.csv")


@pytest.mark.parametrize(
    "row, column",
    [
        (EXTENSION_ROW.replace(",1977.539,", ",-1977.539,"), "rate"),
        (EXTENSION_ROW.replace("music_wire", "unobtainium"), "material"),
    ],
)
def test_cli_rejects_a_bad_catalogue_before_solving(tmp_path, capsys, row, column):
    catalogue = write(tmp_path, HEADER, row)
    out = tmp_path / "design.json"
    # the config is never read: the catalogue fails first
    assert main(["design", str(tmp_path / "config.yaml"), "--stock", str(catalogue), "--out", str(out)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("springbalance: error: ")
    assert "Traceback" not in captured.err and captured.out == ""
    assert str(catalogue) in lines[0] and "line 2" in lines[0] and f"column {column!r}" in lines[0]
    assert not out.exists()


def test_cli_missing_columns_exit_2(tmp_path, capsys):
    catalogue = write(tmp_path, "part_number,type,rate", "X,extension,100")
    out = tmp_path / "design.json"
    assert main(["design", str(tmp_path / "config.yaml"), "--stock", str(catalogue), "--out", str(out)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1
    assert "missing column(s) material, wire_diameter, mean_diameter" in error
    assert not out.exists()
