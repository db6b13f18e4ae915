"""Starts on a pool of worker processes: the same design, bit for bit, as one after another."""

import json
import multiprocessing
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

import springbalance as sb
from config_helpers import SHOULDER_SPRING
from springbalance.cli import main
from springbalance.design import solvers
from springbalance.design.solvers import multistart, pool, solve_problem
from springbalance.io.config import config_from_dict

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.skipif(
    sys.platform == "darwin" or "fork" not in multiprocessing.get_all_start_methods(),
    reason="the pool forks its workers",
)


@pytest.fixture(scope="module")
def arm():
    mechanism = sb.Mechanism.from_urdf(ROOT / "urdf" / "two_link_planar.urdf")
    return mechanism, sb.Workspace.sobol(mechanism, 128, seed=3)


def _springs(keep_tension=True):
    return [
        sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free([-0.2, 0, 0], [0.2, 0, 0.3])),
            sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.5, 0, 0])),
            stiffness=sb.Free(0, 2000),
            free_length=sb.Free(0.02, 0.5),
            keep_tension=keep_tension,
        ),
        sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free([-0.3, 0, -0.1], [0.3, 0, 0.6])),
            sb.Anchor("link2", sb.Free([0.02, 0, 0], [0.4, 0, 0])),
            stiffness=sb.Free(0, 2000),
            free_length=sb.Free(0.02, 0.5),
            keep_tension=keep_tension,
        ),
    ]


def _same(first, second):
    assert np.array_equal(first.x, second.x)
    assert first.status == second.status
    assert len(first.starts) == len(second.starts)
    for a, b in zip(first.starts, second.starts):
        assert (a.index, a.objective, a.max_violation, a.status, a.iterations) == (
            b.index,
            b.objective,
            b.max_violation,
            b.status,
            b.iterations,
        )
        assert np.array_equal(a.x, b.x) and np.array_equal(a.z0, b.z0)


def test_least_squares_starts_and_polish_on_two_workers_equal_the_sequential_run(arm):
    mechanism, workspace = arm
    problem = sb.DesignProblem(mechanism, workspace, _springs())
    options = {"starts": 6, "seed": 4, "max_iterations": 8, "progress": False}  # a small budget: polish runs
    sequential = solve_problem(problem, workers=1, **options)
    pooled = solve_problem(problem, workers=2, **options)
    assert any("polished" in record.status for record in sequential.starts)
    _same(sequential, pooled)


def test_ipopt_starts_on_two_workers_equal_the_sequential_run(arm):
    mechanism, workspace = arm
    problem = sb.DesignProblem(
        mechanism, sb.Workspace.sobol(mechanism, 48, seed=1), _springs(keep_tension=False), objective="peak"
    )
    options = {"starts": 3, "seed": 0, "max_iterations": 30, "progress": False}
    _same(solve_problem(problem, workers=1, **options), solve_problem(problem, workers=2, **options))


def test_design_problem_solve_passes_workers_to_the_solves_it_makes(arm, monkeypatch):
    mechanism, workspace = arm
    seen = []
    original = multistart._pool_workers

    def spy(problem, workers, tasks):
        chosen = original(problem, workers, tasks)
        if tasks > 1:  # (a solve of one start, such as a verification's re-solve, runs here anyway)
            seen.append(chosen)
        return chosen

    monkeypatch.setattr(multistart, "_pool_workers", spy)
    problem = sb.DesignProblem(mechanism, workspace, _springs())
    pooled = sb.solve(problem, starts=3, seed=1, workers=2, max_iterations=20)
    assert seen and seen[0] == (2, True)
    sequential = sb.solve(problem, starts=3, seed=1, workers=1, max_iterations=20)
    assert seen[-1] == (1, True)
    assert np.array_equal(pooled.x, sequential.x)


def test_the_default_number_of_workers(arm, monkeypatch):
    mechanism, workspace = arm
    problem = sb.DesignProblem(mechanism, workspace, _springs())
    monkeypatch.setenv("SPRINGBALANCE_WORKERS", "3")
    assert solvers.default_workers() == 3
    assert pool._pool_workers(problem, None, tasks=8) == (3, False)  # the default, checked before use
    assert pool._pool_workers(problem, None, tasks=2) == (2, False)  # no more workers than starts
    assert pool._pool_workers(problem, 2, tasks=8) == (2, True)  # asked for
    assert pool._pool_workers(problem, 4, tasks=1) == (1, False)
    monkeypatch.delenv("SPRINGBALANCE_WORKERS")
    assert solvers.default_workers() >= 1
    monkeypatch.setenv("SPRINGBALANCE_WORKERS", "0")
    with pytest.raises(sb.InputError, match="SPRINGBALANCE_WORKERS"):
        solvers.default_workers()


def test_by_default_a_pool_opens_only_when_a_start_is_long(arm, monkeypatch):
    mechanism, workspace = arm
    opened = []
    original = pool._StartRunner._pool

    def spy(self):
        opened.append(True)
        return original(self)

    monkeypatch.setattr(pool._StartRunner, "_pool", spy)
    monkeypatch.setenv("SPRINGBALANCE_WORKERS", "2")
    # the rule, not this machine's speed: no start here lasts a minute (a loaded CI machine can make a
    # millisecond start take 0.1 s), so no pool opens
    monkeypatch.setattr(pool, "POOL_MIN_SECONDS", 60.0)
    quick = sb.DesignProblem(mechanism, workspace, _springs(keep_tension=False))
    reference = solve_problem(quick, starts=4, progress=False, workers=1)
    _same(reference, solve_problem(quick, starts=4, progress=False))
    assert not opened
    monkeypatch.setattr(pool, "POOL_MIN_SECONDS", 0.0)  # every start is worth a pool
    _same(reference, solve_problem(quick, starts=4, progress=False))
    assert opened


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2"])
def test_bad_workers_are_refused(arm, bad):
    mechanism, workspace = arm
    problem = sb.DesignProblem(mechanism, workspace, _springs(keep_tension=False))
    with pytest.raises(sb.InputError, match="workers"):
        sb.solve(problem, starts=2, workers=bad)


def test_config_and_command_line_workers(tmp_path, capsys):
    record = {
        "mechanism": {"urdf": str(ROOT / "urdf" / "two_link_planar.urdf")},
        "workspace": {
            "kind": "sobol",
            "n": 64,
            "seed": 0,
            "degrees": True,
            "ranges": {"shoulder": [-90, 90], "elbow": [0, 0]},
        },
        "springs": [SHOULDER_SPRING],
        "weights": {"elbow": 0.0},
        "solve": {"starts": 3, "seed": 0, "workers": 2},
    }
    assert config_from_dict(record).solve_options["workers"] == 2
    with pytest.raises(sb.ConfigError, match="workers"):
        config_from_dict({**record, "solve": {"workers": 0}})
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(record, sort_keys=False))
    designs = []
    for workers in ("1", "2"):
        out = tmp_path / f"design-{workers}.json"
        assert main(["design", str(path), "--out", str(out), "--workers", workers, "--quiet"]) == 0
        designs.append(json.loads(out.read_text()))
    capsys.readouterr()
    assert designs[0]["design"] == designs[1]["design"]


def test_wire_rounding_candidates_on_two_workers_equal_the_sequential_run(monkeypatch):
    """Each coil's two standard wires are re-solved at once, as two starts of one solve on the pool: the
    rounded design is the same, bit for bit, as with one worker."""
    record = yaml.safe_load((ROOT / "examples" / "two_link.yaml").read_text())
    record["workspace"]["n"] = 48
    problem = config_from_dict(record, ROOT / "examples").problem
    pooled_with_held_wires = []
    original = pool._StartRunner._pool

    def spy(self):
        pooled_with_held_wires.append(bool(self.solver.fixed.any()))
        return original(self)

    monkeypatch.setattr(pool._StartRunner, "_pool", spy)
    results = [sb.solve(problem, starts=2, seed=0, workers=workers, progress=False) for workers in (1, 2)]
    assert any(pooled_with_held_wires)  # the rounding solves did run on the pool
    roundings = [result.wire_rounding for result in results]
    assert roundings[0].wires and not roundings[0].unrounded
    assert roundings[0].to_dict() == roundings[1].to_dict()
    assert np.array_equal(results[0].x, results[1].x)
