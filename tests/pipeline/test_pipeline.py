"""springbalance.solve: one entry point from a problem or a config, the steps in order, the problem unchanged."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.clearance import Clearance
from springbalance.design.solvers.multistart import POLISH_FACTOR
from springbalance.errors import InputError
from springbalance.io.catalogue import read_catalogue
from springbalance.io.config import config_from_dict, load_config
from springbalance.pipeline import STEPS, SolveOptions, steps
from springbalance.pipeline.state import COIL_POLISH_FACTOR, FITTED_COIL_POLISH_FACTOR, SolveState

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def pendulum():
    mechanism = sb.Mechanism.from_urdf(ROOT / "urdf/single_link_r2.urdf", gravity=9.8)
    workspace = sb.Workspace.grid(mechanism, 61)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", sb.Free([-0.2, 0, 0.0], [0.2, 0, 0.3])),
        sb.Anchor("link1", sb.Free([0.0, 0, 0], [0.4, 0, 0])),
        stiffness=sb.Free(0, 2000),
    )
    return sb.DesignProblem(mechanism, workspace, [spring])


def test_the_steps_run_in_the_documented_order():
    assert [step.__name__ for step in STEPS] == [
        "first_guess",
        "mount_rows",
        "multi_start",
        "fit_to_arm",
        "round_wires",
        "hold_joints",
        "verify",
    ]


def test_solve_of_a_problem_balances_a_pendulum_exactly(pendulum):
    result = sb.solve(pendulum, starts=2, progress=False)
    assert isinstance(result, sb.DesignResult)
    # a zero-free-length spring from above the pivot balances a pendulum exactly (docs/model.md)
    assert result.exact_balance(tolerance=1e-6)["exact"]
    assert result.metrics()["objectives"]["rms"]["reduction_percent"] > 99.999


def test_the_deprecated_problem_solve_warns_and_gives_the_same_design(pendulum):
    expected = sb.solve(pendulum, starts=2, seed=1, progress=False)
    with pytest.warns(DeprecationWarning, match=r"springbalance\.solve"):
        deprecated = pendulum.solve(starts=2, seed=1, progress=False)
    np.testing.assert_array_equal(deprecated.x, expected.x)


def test_the_deprecated_problem_result_warns_and_wraps_the_design(pendulum):
    x = np.array(pendulum.variables.start)
    with pytest.warns(DeprecationWarning, match="DesignResult"):
        result = pendulum.result(x)
    assert isinstance(result, sb.DesignResult)
    np.testing.assert_array_equal(result.residual_torque(), sb.DesignResult(pendulum, x).residual_torque())


def test_a_config_gives_the_defaults_and_keyword_arguments_win():
    config = load_config(ROOT / "examples/two_link.yaml")
    record = {**config.solve_options}
    options = SolveOptions.merged(record, {"starts": 3, "seed": None})
    assert options.starts == 3 and options.seed == record.get("seed", 0)
    with pytest.raises(InputError, match="unknown solve option"):
        SolveOptions.merged({"start": 2}, {})


def test_coils_get_a_longer_polish_without_a_fit_to_the_arm_and_a_shorter_one_with_it(pendulum):
    coils = load_config(ROOT / "examples/two_link.yaml").problem
    options = SolveOptions(max_iterations=50)
    assert options.for_problem(coils).polish_iterations == COIL_POLISH_FACTOR * 50
    # coils fitted to the arm after the multi-start: its rounds re-solve the design, a short polish
    clear = coils.with_springs(coils.springs, clearance=Clearance(margin=0.005))
    assert options.for_problem(clear).polish_iterations == FITTED_COIL_POLISH_FACTOR * 50
    assert FITTED_COIL_POLISH_FACTOR < POLISH_FACTOR < COIL_POLISH_FACTOR  # the solvers' own default lies between
    # given, it stays; no coils: the solvers' own default
    assert SolveOptions(polish_iterations=7).for_problem(coils).polish_iterations == 7
    assert SolveOptions(polish_iterations=7).for_problem(clear).polish_iterations == 7
    assert options.for_problem(pendulum).polish_iterations is None


def _recorded(monkeypatch, module, name: str, keyword: str) -> list:
    """Wrap ``module.name`` so that each call's ``keyword`` argument is appended to the list returned."""
    seen = []
    real = getattr(module, name)

    def recorded(*args, **kwargs):
        seen.append(kwargs.get(keyword))
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, recorded)
    return seen


def test_every_solve_of_the_steps_gets_the_polish_budget(monkeypatch):
    budgets = _recorded(monkeypatch, steps, "solve_problem", "polish_iterations")
    sb.solve(load_config(ROOT / "examples/two_link.yaml"), starts=2, max_iterations=30, progress=False)
    assert budgets and set(budgets) == {COIL_POLISH_FACTOR * 30}


def test_the_joints_are_held_with_the_wires_the_rounding_chose(monkeypatch):
    """docs/model.md §6, "Held when made worse": the held solve keeps the rounded wires at their standard sizes."""
    from springbalance.design import joint_hold

    fixed = _recorded(monkeypatch, joint_hold, "held_within_bare_arm", "fixed")
    result = sb.solve(load_config(ROOT / "examples/two_link.yaml"), starts=2, max_iterations=30, progress=False)
    assert result.wire_rounding is not None and result.wire_rounding.wires
    assert fixed == [[f"{name}.wire_diameter" for name in result.wire_rounding.wires]]


def test_the_fit_to_the_arm_tightens_the_designs_of_problems_without_free_coils(pendulum, monkeypatch):
    """docs/model.md §11, "Tightening a fitted design": asked for ideal springs, not for free coils."""
    from clearance_helpers import crossing_case
    from springbalance.design import clearance_starts

    coils = load_config(ROOT / "examples/two_link.yaml").problem
    assert steps.tightened(pendulum) and not steps.tightened(coils)
    asked = _recorded(monkeypatch, clearance_starts, "fit_from_starts", "tighten")
    problem, _ = crossing_case(0.005)
    result = sb.solve(problem, starts=2, progress=False)
    assert asked == [True] and result.fit is not None and result.fit.converged


@pytest.mark.parametrize("verify", ["resolve", "report", "off"])
def test_the_fits_are_ranked_at_unseen_poses_in_the_verifications_mode(monkeypatch, verify):
    """docs/model.md §11: of several fits, the lowest that holds where the verification looks (repaired there first
    in mode "resolve"), unless ``verify: off``: the fit is given the solve's mode."""
    from clearance_helpers import crossing_case
    from springbalance.design import clearance_starts

    asked = _recorded(monkeypatch, clearance_starts, "fit_from_starts", "verify")
    problem, _ = crossing_case(0.005)
    sb.solve(problem, starts=2, progress=False, verify=verify)
    assert asked == [verify]


def test_the_fit_starts_from_thin_springs_with_a_clearance_and_no_free_coils(pendulum, monkeypatch):
    """docs/model.md §11: ideal springs with a clearance are fitted as thin lines first; free coils (whose
    capsules are their coils') and problems without a clearance are not."""
    from clearance_helpers import crossing_case
    from springbalance.design import clearance_starts

    problem, _ = crossing_case(0.005)
    coils = load_config(ROOT / "examples/two_link.yaml").problem
    clear_coils = coils.with_springs(coils.springs, clearance=Clearance(margin=0.005))
    assert steps.thin_first(problem) and not steps.thin_first(clear_coils)
    assert not steps.thin_first(pendulum) and not steps.thin_first(coils)
    asked = _recorded(monkeypatch, clearance_starts, "fit_from_starts", "thin_first")
    result = sb.solve(problem, starts=2, progress=False)
    assert asked == [True] and result.fit is not None and result.fit.converged


def test_solve_names_what_it_was_given_when_it_is_neither_a_problem_nor_a_config():
    with pytest.raises(InputError, match="DesignProblem or a Config, got str"):
        sb.solve("examples/two_link.yaml")


def test_solve_leaves_the_problem_unchanged_and_the_result_carries_the_rows():
    """A mounted anchor adds linear rows: they live on the state's copy of the problem, not on the caller's."""
    config = config_from_dict(
        {
            "mechanism": {"urdf": "urdf/two_link_planar_collision.urdf"},
            "workspace": {"kind": "sobol", "n": 32, "seed": 0},
            "springs": [
                {
                    "name": "s1",
                    "type": "zero_free_length",
                    "stiffness": {"lower": 0, "upper": 3000},
                    "a": {"body": "universe", "box": {"lower": [-0.1, 0, 0.05], "upper": [0.1, 0, 0.3]}},
                    "b": {"body": "link1", "on": "collision", "offset": 0.005},
                }
            ],
            "solve": {"starts": 1},
        },
        base_dir=ROOT,
    )
    problem = config.problem
    result = sb.solve(config, progress=False)
    assert problem.linear_rows is None
    assert result.problem is not problem and result.problem.linear_rows is not None
    assert result.fit is not None and result.fit.converged


def test_stock_parts_are_chosen_when_a_catalogue_is_given():
    """The R1 link (8 kg) with an ideal extension spring: solve, then the nearest catalogue parts."""
    mechanism = sb.Mechanism.from_urdf(ROOT / "urdf/single_link_r1.urdf")
    spring = sb.ExtensionSpring(
        sb.Anchor("ground", sb.Free([0, -0.1, 0.05], [0, 0.1, 0.3])),
        sb.Anchor("link1", sb.Free([0, 0, 0.05], [0, 0, 0.4])),
        "s1",
        stiffness=sb.Free(0, 1e4),
        free_length=sb.Free(0.02, 1.0),
        initial_tension=sb.Free(0, 200),
    )
    problem = sb.DesignProblem(mechanism, sb.Workspace.grid(mechanism, n=16), [spring])
    parts = read_catalogue(ROOT / "examples/stock_springs.csv")
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        result = sb.solve(problem, starts=2, progress=False, stock=parts)
    assert result.stock is not None
    chosen = result.stock.parts()
    assert list(chosen) == ["s1"] and chosen["s1"] in {row.part_number for row in parts}
    assert result.problem.springs[0].part_number == chosen["s1"]
    assert result.stock.stock_objective == pytest.approx(result.problem.objective_value(result.evaluation))


def test_a_state_is_a_value(pendulum):
    state = SolveState(pendulum, SolveOptions())
    later = state.but(initial=np.zeros(pendulum.variables.size))
    assert state.initial is None and later.initial is not None and later.problem is pendulum
    with pytest.raises(RuntimeError, match="multi-start"):
        _ = state.solved
