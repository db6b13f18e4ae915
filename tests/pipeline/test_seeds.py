"""``springbalance.solve(..., seeds=[...])``: a design solved at several seeds, the best kept, and every seed's outcome
recorded (pipeline/run.py, results/seed_search.py)."""

from __future__ import annotations

import json

import pytest

import springbalance as sb
from springbalance.errors import InputError
from springbalance.pipeline.state import SolveOptions
from springbalance.results.html_report import head_html
from springbalance.results.result import DesignResult
from two_link_helpers import URDF, spring_per_joint

#: a budget too short for the starts to converge, so that each seed's Sobol starts end at another design
SHORT = {"starts": 3, "max_iterations": 3, "polish_iterations": 0, "progress": False}


@pytest.fixture(scope="module")
def problem():
    """The two-link arm with a spring on each joint, over shoulder ±90° and elbow ±45°."""
    mechanism = sb.Mechanism.from_urdf(URDF)
    workspace = sb.Workspace.grid(mechanism, n=5, ranges={"shoulder": [-90, 90], "elbow": [-45, 45]}, degrees=True)
    springs = spring_per_joint()
    return sb.DesignProblem(mechanism, workspace, springs)


@pytest.fixture(scope="module")
def alone(problem):
    """Each seed's design solved on its own: seed → (objective, failure kinds)."""
    found = {}
    for seed in (0, 1, 2, 4):
        result = sb.solve(problem, seed=seed, **SHORT)
        found[seed] = (problem.objective_at(result.x), tuple(flag.kind for flag in result.failures()))
    return found


def test_the_seeds_give_several_designs_here(alone):
    """The premise of the tests below: at this budget the seeds end at different designs."""
    assert len({objective for objective, _ in alone.values()}) >= 2


def test_the_design_kept_is_the_lowest_of_the_seeds_and_every_seed_is_recorded(problem, alone):
    seeds = [4, 2, 1, 0]
    result = sb.solve(problem, seeds=seeds, **SHORT)
    search = result.seed_search
    assert [run.seed for run in search.runs] == seeds
    for run in search.runs:  # what each seed gave, as its solve alone gives it
        assert run.objective == alone[run.seed][0]
        assert run.failures == alone[run.seed][1]
        assert run.seconds > 0 and run.error is None
    passing = [seed for seed in seeds if not alone[seed][1]]
    lowest = min(alone[seed][0] for seed in passing)
    first_lowest = next(seed for seed in seeds if seed in passing and alone[seed][0] == lowest)
    assert search.kept == first_lowest == result.seed
    assert problem.objective_at(result.x) == lowest
    single = sb.solve(problem, seed=first_lowest, **SHORT)
    assert (result.x == single.x).all()  # the kept design is that seed's own, bit for bit


def test_a_seed_search_is_saved_loaded_and_reported(problem, tmp_path):
    result = sb.solve(problem, seeds=[2, 4], **SHORT)
    path = result.save(tmp_path / "design.json")
    record = json.loads(path.read_text())["solver"]["seeds"]
    assert record["kept"] == result.seed_search.kept
    assert [run["seed"] for run in record["runs"]] == [2, 4]
    loaded = DesignResult.load(path)
    assert loaded.seed_search == result.seed_search
    table = loaded.table()
    assert f"kept the design of seed {result.seed_search.kept}:" in table
    assert sum("← kept" in line for line in table.splitlines()) == 1
    page = "".join(head_html(loaded))
    assert f"Solved at 2 seeds, the design of seed {result.seed_search.kept} kept (2: " in page


def test_a_design_solved_at_one_seed_has_no_seed_search(problem):
    result = sb.solve(problem, seed=1, **SHORT)
    assert result.seed_search is None
    assert "seeds" not in result.to_dict()["solver"]
    assert "kept the design of seed" not in result.table()


@pytest.mark.parametrize(
    ("given", "overrides", "seed", "seeds"),
    [
        ({"seed": 3}, {"seeds": [1, 2]}, 0, (1, 2)),  # seeds asked for: the given seed does not apply
        ({"seeds": [1, 2]}, {"seed": 5}, 5, None),  # one seed asked for wins over the given seeds
        ({"seeds": [4, 0]}, {}, 0, (4, 0)),  # the order is kept
        ({}, {"seed": None, "seeds": None}, 0, None),
    ],
)
def test_seed_and_seeds_override_each_other(given, overrides, seed, seeds):
    options = SolveOptions.merged(given, overrides)
    assert (options.seed, options.seeds) == (seed, seeds)


@pytest.mark.parametrize(
    ("given", "overrides", "message"),
    [
        ({"seed": 1, "seeds": [0, 1]}, {}, "solve section: both seed and seeds given"),
        ({}, {"seed": 1, "seeds": [0, 1]}, "options: both seed and seeds given"),
        ({}, {"seeds": []}, "non-empty"),
        ({}, {"seeds": [0, 0]}, "distinct"),
        ({}, {"seeds": [1, -2]}, "integers >= 0"),
        ({}, {"seeds": "0-4"}, "a list of integers"),
        ({}, {"seeds": [0.5]}, "integers >= 0"),
    ],
)
def test_bad_seeds_are_refused_with_the_value_named(given, overrides, message):
    with pytest.raises(InputError, match=message):
        SolveOptions.merged(given, overrides)


def test_ctrl_c_at_a_later_seed_keeps_the_best_finished_design(problem, alone, monkeypatch):
    """Ctrl-C while the third seed solves: the interruption carries the better of the two finished designs."""
    from springbalance.errors import Interrupted
    from springbalance.pipeline import run

    real, calls = run.run_steps, []

    def steps(problem, options):
        calls.append(options.seed)
        if len(calls) == 3:
            raise Interrupted("interrupted while solving", problem=problem)
        return real(problem, options)

    monkeypatch.setattr(run, "run_steps", steps)
    with pytest.raises(Interrupted) as stop:
        sb.solve(problem, seeds=[4, 0, 2], **SHORT)
    assert calls == [4, 0, 2]
    best = min((4, 0), key=lambda seed: (bool(alone[seed][1]), len(alone[seed][1]), alone[seed][0]))
    assert f"interrupted at seed 2 (2 of 3 seeds finished, the design of seed {best} the best)" in str(stop.value)
    assert (stop.value.best_x == real(problem, SolveOptions.merged({}, {**SHORT, "seed": best})).x).all()


def test_with_progress_each_seed_is_announced_before_its_bars(problem, capsys):
    sb.solve(problem, seeds=[4, 0], **{**SHORT, "progress": True})
    err = capsys.readouterr().err
    assert err.index("seed 4 (1 of 2)") < err.index("seed 0 (2 of 2)")
    sb.solve(problem, seeds=[4, 0], **SHORT)  # progress off: nothing
    assert "of 2)" not in capsys.readouterr().err
