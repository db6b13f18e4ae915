"""Tasks run ahead on forked workers (:mod:`springbalance.design.solvers.forked`): the results of the needed
tasks, as one after the other; a task found not needed is stopped; clearance fits side by side give the fit
of one after the other, bit for bit."""

import multiprocessing
import os
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from clearance_helpers import crossing_springs
from springbalance.design import clearance_starts
from springbalance.design.solvers import forked, solve_problem, workers_default

URDF = Path(__file__).resolve().parents[2] / "urdf"
pytestmark = pytest.mark.skipif(
    sys.platform == "darwin" or "fork" not in multiprocessing.get_all_start_methods(),
    reason="the workers are forked",
)


def _task(index: int):
    return lambda: (index, os.getpid(), index * index)


def test_the_needed_tasks_in_order_on_workers_as_one_after_the_other():
    asked = []

    def needed(index, done):
        asked.append((index, [result[0] for result in done]))
        return sum(result[2] for result in done) < 5  # 0 + 1 + 4 = 5: task 3 is not needed

    tasks = [_task(index) for index in range(6)]
    with workers_default(1):
        alone = forked.run_in_order(None, tasks, needed)
    with workers_default(2):
        ahead = forked.run_in_order(None, tasks, needed)
    assert [result[0] for result in alone] == [0, 1, 2]
    assert [(r[0], r[2]) for r in ahead] == [(r[0], r[2]) for r in alone]
    assert {result[1] for result in alone} == {os.getpid()}
    assert os.getpid() not in {result[1] for result in ahead}  # they ran on the workers
    # each task's need asked once, with the results of every task before it, in both runs
    assert asked[:3] == [(1, [0]), (2, [0, 1]), (3, [0, 1, 2])] == asked[3:]


def test_a_task_found_not_needed_is_stopped(tmp_path):
    marker = tmp_path / "written"

    def slow():
        time.sleep(2.0)
        marker.write_text("task 1 ran to its end")
        return 1

    with workers_default(2):
        results = forked.run_in_order(None, [lambda: 0, slow], lambda index, done: False)
    assert results == [0]
    time.sleep(3.0)  # task 1 would have written its file by now, had its worker not been terminated
    assert not marker.exists()


def test_an_error_in_a_task_reaches_the_caller():
    def failing():
        raise ValueError("task 1 failed")

    with workers_default(2), pytest.raises(ValueError, match="task 1 failed"):
        forked.run_in_order(None, [lambda: 0, failing], lambda index, done: True)


def test_clearance_fits_side_by_side_equal_one_after_the_other():
    arm = sb.Mechanism.from_urdf(URDF / "two_link_planar_collision.urdf")
    workspace = sb.Workspace.sobol(arm, n=128, seed=0)
    clearance = sb.Clearance(margin=0.005, check_samples=64)
    # in the arm's plane, the best design of seed 0 crosses link2: its fit moves it, so the next one is fitted too
    # (and one more: each carries the elbow's peak above the bare arm's, clearance_round.fall_back)
    problem = sb.DesignProblem(arm, workspace, crossing_springs(0.0), clearance=clearance)
    options = {"method": "auto", "max_iterations": 100, "tolerance": 1e-8}
    solution = solve_problem(problem, starts=4, seed=0, workers=1, **options)
    fits = []
    for workers in (1, 2):
        with workers_default(workers):
            fits.append(clearance_starts.fit_from_starts(problem, solution, **options))
    (first, record, fitted), (second, other, fitted_again) = fits
    assert record.starts == other.starts >= 2
    assert np.array_equal(first.x, second.x) and first.status == second.status
    assert (record.rounds, record.converged, record.objective) == (other.rounds, other.converged, other.objective)
    rows, rows_again = fitted.linear_rows, fitted_again.linear_rows  # none when the design kept was clear as it stood
    assert (rows is None) == (rows_again is None)
    assert rows is None or np.array_equal(rows.matrix, rows_again.matrix)
