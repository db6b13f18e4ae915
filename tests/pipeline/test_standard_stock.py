"""A stock design from the standard catalogues: the desk lamp (urdf/desk_lamp.urdf, 0.3 kg at 0.15 m, ±90°)
balanced by real MS24586 / MS24585 parts, from Python, a config's solve.stock and the command line."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import springbalance as sb
from springbalance.cli import main
from springbalance.design.worse_joints import weighted_joints_made_worse
from springbalance.pipeline.stock import select_stock
from springbalance.springs.fatigue import Duty, fatigue_margins
from springbalance.springs.tolerance_grades import grade_box

ROOT = Path(__file__).resolve().parents[2]
LAMP = ROOT / "urdf" / "desk_lamp.urdf"
EXAMPLE = ROOT / "examples" / "desk_lamp.yaml"
#: gravity torque at the pivot: m g s sin q, largest at ±90°
PEAK_TORQUE = 0.3 * 9.81 * 0.15  # [N·m]


def lamp(*springs):
    mechanism = sb.Mechanism.from_urdf(LAMP)
    return sb.DesignProblem(mechanism, sb.Workspace.grid(mechanism, n=16), list(springs))


@pytest.fixture(scope="module")
def extension_design():
    lift = sb.HelicalExtensionSpring(
        sb.Anchor("ground", sb.Free([0, -0.02, 0.02], [0, 0.02, 0.15])),
        sb.Anchor("arm", sb.Free([0, 0, 0.01], [0, 0, 0.15])),
        "lift",
    )
    return sb.solve(lamp(lift), starts=2, progress=False, stock=sb.load_stock("ms24586"))


def test_a_stock_design_keeps_the_users_no_joint_worse():
    """The part's re-solve is a problem like the user's, no_joint_worse included (it used to be dropped: the stock
    design's problem, and the design file, said no_joint_worse false)."""
    lift = sb.HelicalExtensionSpring(
        sb.Anchor("ground", sb.Free([0, -0.02, 0.02], [0, 0.02, 0.15])),
        sb.Anchor("arm", sb.Free([0, 0, 0.01], [0, 0, 0.15])),
        "lift",
    )
    problem = lamp(lift).with_springs([lift], no_joint_worse=True)
    result = sb.solve(problem, starts=2, progress=False, stock=sb.load_stock("ms24586"))
    assert result.stock is not None and result.problem.no_joint_worse
    assert result.to_dict()["no_joint_worse"] is True  # the design file says what the user asked for
    assert weighted_joints_made_worse(result.problem, result.x) == [] and result.ok, result.failures()


def test_the_lamp_is_balanced_by_an_ms24586_part(extension_design):
    result = extension_design
    catalogue = {part.part_number: part for part in sb.load_stock("ms24586")}
    (choice,) = result.stock.choices
    assert choice.spring == "lift" and choice.part == catalogue[choice.part.part_number]
    record = result.spring("lift")
    assert record["part_number"] == choice.part.part_number
    assert record["stiffness"] == pytest.approx(choice.part.rate, rel=1e-6)
    assert record["initial_tension"] == pytest.approx(choice.part.initial_tension)
    # the part's spec sheet is checked like a wound coil: its loads stay within the rules
    sheet = record["helical"]
    assert sheet["part_number"] == choice.part.part_number and sheet["buildable"], sheet["reasons"]
    assert sheet["max_stress"] <= sheet["allowable_stress"]
    assert result.ok, result.failures()
    joint = result.metrics()["joints"][0]
    assert joint["peak_before"] == pytest.approx(PEAK_TORQUE, rel=1e-3)
    # one spring from above the pivot nearly balances a single link (a zero-free-length-like line)
    assert joint["rms_reduction_percent"] > 90
    summary = result.stock.summary()
    assert f"→ {choice.part.part_number} (extension, " in summary


def test_the_chosen_part_is_checked_for_fatigue_and_tolerance(extension_design):
    result = extension_design
    (choice,) = result.stock.choices
    part = choice.part
    # the force range the part sees: its own law F_i + k (L − l0) at the stock design's lengths
    lengths = result.evaluation.lengths[:, 0]
    forces = part.initial_tension + part.rate * (lengths - part.free_length)
    fatigue = choice.fatigue
    assert fatigue.duty == Duty()  # 10⁶ cycles, n_f ≥ 1.2, Gerber: the default duty of a coil
    assert fatigue.min_force == pytest.approx(forces.min(), rel=1e-5)
    assert fatigue.max_force == pytest.approx(forces.max(), rel=1e-5)
    expected = fatigue_margins(
        part.wire_diameter, part.mean_diameter, part.material, forces.min(), forces.max(), kind="extension"
    )
    assert set(fatigue.margins) == {"body", "hook_bending", "hook_torsion"}
    for location, margin in expected.items():
        assert fatigue.margins[location].safety_factor == pytest.approx(margin.safety_factor, rel=1e-4)
    assert fatigue.holds  # a candidate that fails its duty is never chosen
    # tolerance: the part's grade-2 box (EN 15800 / DIN 2097) and the adjuster that restores the balance
    box = grade_box(
        "extension", part.wire_diameter, part.mean_diameter, part.active_coils, part.free_length, part.rate,
        part.initial_tension,
    )  # fmt: skip
    assert choice.tolerance["box"]["rate"] == pytest.approx(box.rate)
    assert choice.tolerance["box"]["initial_tension"] == pytest.approx(box.initial_tension, rel=1e-6)
    assert choice.tolerance["travel"] > 0
    (joint,) = result.stock.tolerance.joints
    assert joint["worst_peak"] >= joint["peak"]  # the box holds the nominal part
    assert joint["adjusted_peak"] < joint["worst_peak"]
    summary = result.stock.summary()
    assert "fatigue ok (1e+06 cycles, gerber" in summary and "tolerance grade 2: k ± 1.5 %" in summary
    record = result.stock.to_dict()
    assert record["choices"][0]["fatigue"]["holds"] is True and record["tolerance"]["joints"][0]["joint"] == "pivot"


def test_a_part_that_cannot_live_its_duty_is_not_chosen():
    # fixed anchors: the parts' solves have nothing to steer (no fatigue rows), so each candidate is feasible
    # and the check of its force range under the duty is what turns it down
    lift = sb.ExtensionSpring(
        sb.Anchor("ground", [0, 0, 0.15]),
        sb.Anchor("arm", [0, 0, 0.05]),
        "lift",
        stiffness=sb.Free(0, 1e4),
        free_length=sb.Free(0.01, 0.3),
        initial_tension=sb.Free(0, 100),
    )
    # a duty no wire survives, n_f ≥ 50; an ideal law takes no duty record, so it is set as the coil's attribute
    lift.duty = Duty(safety_factor=50.0)
    problem = lamp(lift)
    continuous = sb.solve(problem, starts=1, progress=False, verify="off")
    with pytest.raises(
        sb.SolverError, match=r"no stock part fits spring 'lift'.*fails fatigue \(body n_f [0-9.]+ < 50"
    ):
        select_stock(problem, continuous, sb.load_stock("ms24586"), candidates=2, starts=1)


def test_stock_parts_for_the_best_of_several_seeds_keep_the_seeds_record():
    """With ``seeds``, the parts replace the kept seed's continuous design, and the stock design keeps the record of
    what each seed gave."""
    lift = sb.HelicalExtensionSpring(
        sb.Anchor("ground", sb.Free([0, -0.02, 0.02], [0, 0.02, 0.15])),
        sb.Anchor("arm", sb.Free([0, 0, 0.01], [0, 0, 0.15])),
        "lift",
    )
    result = sb.solve(lamp(lift), seeds=[1, 0], starts=2, progress=False, stock=sb.load_stock("ms24586"))
    assert result.stock is not None and result.seed_search is not None
    assert [run.seed for run in result.seed_search.runs] == [1, 0]
    assert result.seed == result.seed_search.kept
    assert result.to_dict()["solver"]["seeds"] == result.seed_search.to_dict()


def test_the_springs_duty_goes_with_the_part():
    lift = sb.HelicalExtensionSpring(
        sb.Anchor("ground", sb.Free([0, -0.02, 0.02], [0, 0.02, 0.15])),
        sb.Anchor("arm", sb.Free([0, 0, 0.01], [0, 0, 0.15])),
        "lift",
        duty={"cycles": 1e7},
    )
    result = sb.solve(lamp(lift), starts=2, progress=False, stock=sb.load_stock("ms24586"))
    spring = result.problem.springs[0]
    assert spring.part_number == result.stock.choices[0].part.part_number
    assert spring.duty == Duty(cycles=1e7) == result.stock.choices[0].fatigue.duty
    sheet = result.spring("lift")["helical"]
    assert sheet["duty"]["cycles"] == 1e7 and sheet["buildable"], sheet["reasons"]


def test_a_compression_part_of_ms24585_takes_a_pushing_spring():
    push = sb.HelicalCompressionSpring(
        sb.Anchor("ground", sb.Free([0, -0.02, -0.1], [0, 0.02, -0.01])),
        sb.Anchor("arm", sb.Free([0, 0, 0.01], [0, 0, 0.1])),
        "push",
        guided=True,
    )
    result = sb.solve(lamp(push), starts=2, progress=False, stock=sb.load_stock("ms24585,ms24586"))
    (choice,) = result.stock.choices
    assert choice.kind == "compression" and choice.part.part_number.startswith("MS24585")
    sheet = result.spring("push")["helical"]
    assert sheet["part_number"] == choice.part.part_number and sheet["buildable"], sheet["reasons"]
    # MS24585 parts are at most 38.1 mm long: the design is worse than the free coil, but it helps
    assert result.evaluation.max_violation <= 1e-6
    assert result.stock.stock_objective >= result.stock.continuous_objective
    assert result.metrics()["joints"][0]["rms_after"] < result.metrics()["joints"][0]["rms_before"]


def test_cli_design_takes_the_configs_stock_and_the_command_lines(tmp_path, capsys):
    out = tmp_path / "lamp.json"
    assert main(["design", str(EXAMPLE), "--out", str(out), "--quiet"]) == 0
    record = json.loads(out.read_text())
    number = record["stock"]["parts"]["lift"]
    assert record["stock"]["catalogue"] == "ms24586" and number.startswith("MS24586")
    assert record["design"][0]["part_number"] == number

    assert main(["design", str(EXAMPLE), "--out", str(out), "--stock", "ms24585,ms24586"]) == 0
    printed = capsys.readouterr().out
    record = json.loads(out.read_text())
    assert record["stock"]["catalogue"] == "ms24585,ms24586"
    assert f"→ {record['stock']['parts']['lift']} (extension" in printed
