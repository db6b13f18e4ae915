"""Stock springs: a continuous design's coil springs replaced by catalogue parts, anchors re-optimised."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
import yaml

import springbalance as sb
from springbalance.cli import main
from springbalance.design.stock import StockPart, part_distance, part_spring, warm_started
from springbalance.io.catalogue import read_catalogue
from springbalance.pipeline.stock import select_stock

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "urdf" / "single_link_r1.urdf"
CATALOGUE = ROOT / "examples" / "stock_springs.csv"


@pytest.fixture(scope="module")
def parts():
    return read_catalogue(CATALOGUE)


def link_problem(*springs):
    """The R1 rotating link (8 kg, 120°–180°) on a 16-point grid with the given springs."""
    mechanism = sb.Mechanism.from_urdf(URDF)
    return sb.DesignProblem(mechanism, sb.Workspace.grid(mechanism, n=16), list(springs))


def extension(name="s1", **options):
    """An ideal extension spring from the ground above the pivot to the link, anchors free in boxes."""
    return sb.ExtensionSpring(
        sb.Anchor("ground", sb.Free([0, -0.1, 0.05], [0, 0.1, 0.3])),
        sb.Anchor("link1", sb.Free([0, 0, 0.05], [0, 0, 0.4])),
        name,
        stiffness=sb.Free(0, 1e4),
        free_length=sb.Free(0.02, 1.0),
        initial_tension=sb.Free(0, 200),
        **options,
    )


def compression(name="s2"):
    """A compression spring from the ground below the pivot to the link, on a guide rod (``guided``: the
    catalogue's long compression parts would buckle free-standing)."""
    return sb.HelicalCompressionSpring(
        sb.Anchor("ground", sb.Free([0, -0.1, -0.3], [0, 0.1, -0.02])),
        sb.Anchor("link1", sb.Free([0, 0, 0.05], [0, 0, 0.4])),
        name,
        guided=True,
    )


def row(parts, part_number):
    return next(part for part in parts if part.part_number == part_number)


def assert_is_part(record, spring, part):
    """The design's spring values and options are exactly the catalogue row's."""
    assert spring.part_number == part.part_number
    for key in ("wire_diameter", "mean_diameter", "active_coils"):
        assert record[key] == getattr(part, key)
    assert record["stiffness"] == pytest.approx(part.rate, rel=1e-6)  # G d⁴/(8 D³ n); the CSV keeps 7 digits
    assert record["free_length"] == pytest.approx(part.free_length, rel=1e-6)
    if part.kind == "extension":
        assert record["initial_tension"] == part.initial_tension
        assert spring.max_length == part.max_length and spring.keep_tension
    else:
        assert record["preload"] == 0.0 and record["free_length"] == part.free_length
        assert record["helical"]["solid_length"] == pytest.approx(part.min_length, rel=1e-6)
    assert spring.max_force == part.max_load
    assert record["helical"]["part_number"] == part.part_number  # a spec sheet, as for a wound coil


# ---------------------------------------------------------------------- parts as springs
def test_part_spring_keeps_name_and_anchors_and_takes_the_parts_values(parts):
    spring = extension(max_force=1e4, max_length=0.3, min_length=0.1)
    part = row(parts, "EXT-MW-d3.0-C10-n40")
    stock = part_spring(part, spring)
    assert isinstance(stock, sb.HelicalExtensionSpring)
    assert stock.name == "s1" and stock.a is spring.a and stock.b is spring.b
    assert stock.parameters == {
        "wire_diameter": part.wire_diameter,
        "mean_diameter": part.mean_diameter,
        "active_coils": part.active_coils,
        "initial_tension": part.initial_tension,
    }
    assert stock.rate(stock.parameters) == pytest.approx(part.rate, rel=1e-6)
    assert stock.free_length(stock.parameters) == pytest.approx(part.free_length, rel=1e-6)
    assert stock.part_number == part.part_number and stock.keep_tension
    assert stock.max_force == part.max_load  # the part's limit is stricter than 1e4 N
    assert stock.max_length == 0.3 and stock.min_length == 0.1  # the arm's limits are stricter
    assert stock.to_dict()["part_number"] == part.part_number

    part = row(parts, "CMP-MW-d4.0-C8-n16")
    stock = part_spring(part, compression())
    assert isinstance(stock, sb.HelicalCompressionSpring)
    assert stock.parameters == {
        "wire_diameter": part.wire_diameter,
        "mean_diameter": part.mean_diameter,
        "active_coils": part.active_coils,
        "free_length": part.free_length,
    }
    assert stock.rate(stock.parameters) == pytest.approx(part.rate, rel=1e-6) and stock.stays_compressed

    with pytest.raises(sb.InputError, match="is a compression spring; spring 's1' is a extension"):
        part_spring(part, extension())
    gas = sb.GasSpring(sb.Anchor("ground"), sb.Anchor("link1", [0, 0, 0.2]), "g", stiffness=1, free_length=0.5)
    with pytest.raises(sb.InputError, match="cannot be a catalogue part"):
        part_spring(part, gas)


def test_part_distance_is_zero_for_the_same_force_line_and_grows_with_shortfalls():
    part = StockPart("P", "extension", "music_wire", 0.002, 0.016, 20, 0.07, 10.0, 1977.539, 150.0, 0.13, 0.07)
    lengths = np.linspace(0.08, 0.12, 5)
    forces = part.initial_tension + part.rate * (lengths - part.free_length)
    assert part_distance(part, lengths, forces) == pytest.approx(0.0, abs=1e-12)
    assert part_distance(part, lengths, 1.1 * forces) == pytest.approx(
        0.1 / 1.1 * np.sqrt(np.mean(forces**2)) / forces.max()
    )
    weak = dataclasses.replace(part, max_load=forces.max() / 2)
    assert part_distance(weak, lengths, forces) == pytest.approx(np.log(2.0))
    short = dataclasses.replace(part, max_length=part.free_length + 0.02)  # stroke 20 mm of the 40 mm needed
    assert part_distance(short, lengths, forces) == pytest.approx(np.log(2.0))


def test_warm_start_puts_every_free_variable_at_the_optimum():
    problem = link_problem(extension())
    x = problem.scale(np.full(problem.variables.size, 0.3))
    springs = warm_started(problem, x)
    again = link_problem(*springs)
    assert again.variables.names == problem.variables.names
    np.testing.assert_allclose(again.variables.start, x, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(again.variables.bounds(), problem.variables.bounds())


# ---------------------------------------------------------------------- selection
def test_select_stock_replaces_each_coil_spring_by_a_catalogue_row(parts):
    problem = link_problem(extension("s1"), compression("s2"))
    continuous = sb.solve(problem, starts=2, progress=False)
    selection = select_stock(problem, continuous, parts, candidates=3, starts=1)
    result = selection.result

    assert [choice.spring for choice in selection.choices] == ["s1", "s2"]
    for spring, choice in zip(result.problem.springs, selection.choices):
        part = row(parts, choice.part.part_number)  # the chosen part is a catalogue row, exactly
        assert choice.part == part
        assert_is_part(result.spring(spring.name), spring, part)
        assert len(choice.trials) == 3 and choice.objective == min(
            t.objective for t in choice.trials if t.objective is not None
        )
        assert [trial.distance for trial in choice.trials] == sorted(trial.distance for trial in choice.trials)
    assert selection.parts() == {choice.spring: choice.part.part_number for choice in selection.choices}

    # the same objective, workspace and weights; only the anchors are left to optimise
    assert result.problem.objective.name == "rms"
    assert result.problem.variables.names == [
        name for name in problem.variables.names if ".a." in name or ".b." in name
    ]
    assert result.evaluation.max_violation <= 1e-6
    assert selection.continuous_objective == pytest.approx(problem.objective_value(continuous.evaluation))
    assert selection.stock_objective == pytest.approx(result.problem.objective_value(result.evaluation))
    assert selection.stock_objective >= selection.continuous_objective
    assert selection.cost == pytest.approx(selection.stock_objective - selection.continuous_objective)
    # a stock design still balances most of the link
    assert result.metrics()["joints"][0]["rms_reduction_percent"] > 80

    summary = selection.summary()
    assert all(choice.part.part_number in summary for choice in selection.choices)
    assert "objective rms: continuous" in summary and "→ stock" in summary
    json.dumps(selection.to_dict())  # the record is plain JSON
    record = result.to_dict()
    assert [spring["part_number"] for spring in record["springs"]] == list(selection.parts().values())


def test_no_part_fits_names_the_spring(parts):
    problem = link_problem(extension("lifter"))
    continuous = sb.solve(problem, starts=1, progress=False)
    # the anchors are always ≥ 0.1 m apart: a part that may not stretch beyond 40 mm never fits
    tiny = StockPart("TINY", "extension", "music_wire", 0.0008, 0.0048, 10, 0.0168, 5.153, 3750.0, 34.769, 0.04, 0.0168)
    with pytest.raises(sb.SolverError, match="no stock part fits spring 'lifter'.*TINY"):
        select_stock(problem, continuous, [tiny], starts=1)
    only_compression = [part for part in parts if part.kind == "compression"]
    with pytest.raises(sb.SolverError, match="no stock part fits spring 'lifter': the catalogue holds no extension"):
        select_stock(problem, continuous, only_compression, starts=1)


def test_nothing_to_take_from_the_catalogue(parts):
    gas = sb.GasSpring(
        sb.Anchor("ground", [0, 0, -0.1]),
        sb.Anchor("link1", [0, 0, 0.2]),
        "g",
        stiffness=sb.Free(0, 1e3),
        free_length=sb.Free(0.3, 1.0),
    )
    problem = link_problem(gas)
    with pytest.raises(sb.InputError, match=r"no spring to take from the catalogue.*g \(gas\)"):
        select_stock(problem, problem.variables.start, parts)
    with pytest.raises(sb.InputError, match="holds no parts"):
        select_stock(link_problem(extension()), link_problem(extension()).variables.start, [])


# ---------------------------------------------------------------------- command line
def test_cli_design_with_stock(tmp_path, capsys, parts):
    config = {
        "mechanism": {"urdf": str(URDF)},
        "workspace": {"kind": "grid", "n": 16},
        "springs": [extension("lifter").to_dict()],
        "solve": {"starts": 2, "seed": 0},
    }
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config, sort_keys=False))
    out = tmp_path / "design.json"
    assert main(["design", str(path), "--stock", str(CATALOGUE), "--out", str(out)]) == 0
    printed = capsys.readouterr().out

    record = json.loads(out.read_text())
    number = record["springs"][0]["part_number"]
    part = row(parts, number)
    assert record["design"][0]["part_number"] == number
    assert record["design"][0]["stiffness"] == pytest.approx(part.rate, rel=1e-6)
    assert record["design"][0]["free_length"] == pytest.approx(part.free_length, rel=1e-6)
    assert record["design"][0]["initial_tension"] == part.initial_tension
    stock = record["stock"]
    assert stock["catalogue"] == str(CATALOGUE) and stock["parts"] == {"lifter": number}
    assert stock["stock_objective"] == pytest.approx(record["metrics"]["objectives"]["rms"]["after"])
    assert stock["continuous_objective"] < stock["stock_objective"]

    assert f"→ {number}" in printed
    assert "objective rms: continuous" in printed and f"design saved to {out}" in printed

    loaded = sb.DesignResult.load(out)  # a stock design loads back as a fixed spring
    assert loaded.problem.springs[0].part_number == number
    assert loaded.spring("lifter")["stiffness"] == pytest.approx(part.rate, rel=1e-6)
