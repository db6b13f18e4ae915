"""The wire sizes a spring maker draws (``solve.wire_sizes``): the rounding rounds to them, the report judges
each wire against them, and a design file keeps them (springbalance.design.standard_wire, results.range_flags).

The demo (examples/two_link.yaml) rounds its three continuous wires, 3.038, 3.077 and 5.371 mm, to the
preferred 3.0, 3.0 and 5.0 mm. Given sizes between which those wires lie (2.8 / 3.1 / 3.4 and 5.2 / 5.6 mm,
3.1 and 5.2 mm being off the preferred series), each wire must land on a neighbour of its continuous value
in that list.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design import standard_wire
from springbalance.errors import InputError
from springbalance.io.config import config_from_dict, read_config_file
from springbalance.springs.sizing import PREFERRED_WIRE_DIAMETERS

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "two_link.yaml"
SIZES = [0.0034, 0.0028, 0.0031, 0.0052, 0.0056]  # [m], unsorted on purpose


def _demo(**solve: object):
    record = copy.deepcopy(read_config_file(EXAMPLE))
    record["solve"] = {**record.get("solve", {}), **solve}
    return config_from_dict(record, EXAMPLE.parent, "two_link (test)")


@pytest.fixture(scope="module")
def rounded() -> sb.DesignResult:
    return sb.solve(_demo(wire_sizes=SIZES), progress=False)


def test_each_wire_is_rounded_to_a_neighbour_in_the_given_sizes(rounded):
    assert rounded.wire_sizes == tuple(sorted(SIZES))
    sizes = np.array(sorted(SIZES))
    assert set(rounded.wire_rounding.wires) == {"shoulder_spring", "forearm_spring", "elbow_spring"}
    for continuous, standard in rounded.wire_rounding.wires.values():
        below, above = sizes[sizes <= continuous], sizes[sizes >= continuous]
        assert standard in {float(below.max()), float(above.min())}
    by_name = {record["name"]: record["wire_diameter"] for record in rounded.springs}
    assert any(all(abs(wire - size) > 1e-9 for size in PREFERRED_WIRE_DIAMETERS) for wire in by_name.values())
    assert rounded.evaluation.max_violation <= 1e-6
    assert "standard wire (of solve.wire_sizes, 5 sizes):" in rounded.table()


def test_a_wire_of_the_given_sizes_is_not_off_series_and_the_file_keeps_them(rounded, tmp_path):
    """Off the preferred series (3.1, 5.2 mm) but on the maker's: no warning, also once saved and loaded; the same
    wires judged against the preferred series are off it."""
    assert "off_series_wire" not in [flag.kind for flag in rounded.warnings()]
    path = tmp_path / "design.json"
    rounded.save(path)
    loaded = sb.DesignResult.load(path)
    assert loaded.wire_sizes == tuple(sorted(SIZES))
    assert "off_series_wire" not in [flag.kind for flag in loaded.warnings()]
    loaded.wire_sizes = None  # the preferred series
    off = [flag for flag in loaded.warnings() if flag.kind == "off_series_wire"]
    assert off and all("not a preferred size" in flag.message for flag in off)


def test_a_wire_off_the_given_sizes_is_flagged_against_them(rounded):
    result = copy.copy(rounded)
    result.wire_sizes = (0.0029, 0.0033)  # none of the design's wires
    (first, *_) = [flag for flag in result.warnings() if flag.kind == "off_series_wire"]
    assert "not one of solve.wire_sizes" in first.message


@pytest.mark.parametrize(
    ("sizes", "words"),
    [
        ([3.2, 4.0], "in metres (3.2 mm is 0.0032)"),
        ([], "at least 1"),
        ([0.003, 0.003], "must be distinct"),
        ([-0.001], "must be > 0"),
        (0.003, "expected a list"),
    ],
)
def test_bad_wire_sizes_name_the_key(sizes, words):
    with pytest.raises(sb.ConfigError) as error:
        _demo(wire_sizes=sizes)
    assert "solve.wire_sizes" in str(error.value) and words in str(error.value)


def test_the_python_option_is_checked_too():
    with pytest.raises(InputError, match=r"wire_sizes: each wire diameter must lie in \(0, 0.05\) m, got 4.0"):
        standard_wire.checked_wire_sizes([0.003, 4.0])
    with pytest.raises(InputError, match="must be distinct"):
        standard_wire.checked_wire_sizes([0.003, 0.003])
    assert standard_wire.checked_wire_sizes([0.004, 0.003]) == (0.003, 0.004)


def test_standard_wire_and_the_polish_budget_are_config_keys():
    """``solve.standard_wire: false`` leaves the wires continuous (the off_series_wire warning's hint names it)."""
    config = _demo(standard_wire=False, polish_iterations=0)
    assert config.solve_options["standard_wire"] is False and config.solve_options["polish_iterations"] == 0
    result = sb.solve(config, progress=False)
    assert result.wire_rounding is None
    assert "off_series_wire" in [flag.kind for flag in result.warnings()]
