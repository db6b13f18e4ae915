"""How the coil search starts, polishes and rounds (issue 27): the twin's distinct optima as starts, the
polish of a start the budget stopped short of feasible below the best feasible one, and the wires rounded
together in one solve."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from springbalance.design import coil_start, standard_wire
from springbalance.design.solvers import StartRecord, multistart, polish
from springbalance.io.config import load_config
from springbalance.pipeline import solve
from springbalance.springs.sizing import PREFERRED_WIRE_DIAMETERS


def _demo():
    return load_config("examples/two_link.yaml").problem


def test_coil_starts_are_distinct_wound_designs_within_the_bounds_best_first():
    problem = _demo()
    found = coil_start.coil_starts(problem, 3, starts=4, seed=0, method="auto", max_iterations=100, tolerance=1e-8)
    assert found is not None
    starts = found.starts
    assert starts.ndim == 2 and 1 <= starts.shape[0] <= 3 and starts.shape[1] == problem.variables.size
    lower, upper = problem.variables.bounds()
    assert np.all(starts >= lower - 1e-12) and np.all(starts <= upper + 1e-12)
    for i in range(starts.shape[0]):
        for j in range(i):
            assert not np.allclose(starts[i], starts[j])
    # the first is the twin's best, the one coil_start gives
    first = coil_start.coil_start(problem, starts=4, seed=0, method="auto", max_iterations=100, tolerance=1e-8)
    assert np.allclose(starts[0], first)
    # the twin's optimum balances better than no springs: its objective is below the unbalanced one
    twin = found.twin
    kinematics = twin.workspace.kinematics()
    unbalanced = twin.objective.value(kinematics.gravity_torque * twin.weights, kinematics.potential, twin.path_steps)
    assert twin.objective_value(twin.evaluate(found.twin_x)) < 0.2 * unbalanced


class _Continues:
    """A start runner whose polish turns every continued start feasible at its own objective (the selection
    logic of the polish is what is tested, not a solver)."""

    def __init__(self):
        self.continued = []

        class _Solver:
            max_iterations = 100

        self.solver = _Solver()

    def run(self, tasks):
        records = []
        for index, _, _, _ in tasks:
            self.continued.append(index)
            records.append(_record(index, self.objectives[index], 0.0, "ipopt: Solve_Succeeded"))
        return records


def _record(index, objective, violation, status):
    x = np.full(2, float(index))
    return StartRecord(index, x, x, objective, violation, status, 100, 0.1)


class _Problem:
    class objective:  # stands for an objective without a first phase
        first_phase = None

    @staticmethod
    def unscale(x):
        return x


def test_a_start_stopped_short_of_feasible_below_the_best_feasible_one_is_polished():
    """Start 0 ends infeasible at objective 0.75 on the budget, start 3 feasible at 16.7 (worse than no
    springs on the UR5): the polish continues start 0, which then wins."""
    records = [
        _record(0, 0.75, 0.002, "ipopt: Maximum_Iterations_Exceeded"),
        _record(1, 0.77, 0.003, "ipopt: Maximum_Iterations_Exceeded"),
        _record(2, 29.4, 5.0, "ipopt: Maximum_Iterations_Exceeded"),
        _record(3, 16.7, 0.0, "least_squares: converged"),
    ]
    runner = _Continues()
    runner.objectives = {0: 0.37, 1: 0.38, 2: 29.4, 3: 16.7}
    best = polish.polished_best(_Problem(), runner, records, 400, 4)
    assert runner.continued == [0, 1]  # the two promising ones (PROMISING_INFEASIBLE), best first; not start 2
    assert best.index == 0 and best.feasible and best.objective == 0.37


def test_an_infeasible_start_above_the_best_feasible_one_is_not_polished():
    records = [
        _record(0, 2.0, 0.002, "ipopt: Maximum_Iterations_Exceeded"),
        _record(1, 1.0, 0.0, "ipopt: Solve_Succeeded"),
    ]
    runner = _Continues()
    runner.objectives = {0: 0.5, 1: 1.0}
    best = polish.polished_best(_Problem(), runner, records, 400, 2)
    assert runner.continued == [] and best.index == 1


def test_the_demo_wires_are_rounded_together_to_preferred_sizes():
    """Three coils: one solve rounds every wire (the status says so); each wire is a preferred size next to
    its continuous value, and the rounding costs at most JOINT_ACCEPT of the gap to the unbalanced arm."""
    result = solve(load_config("examples/two_link.yaml"), progress=False)
    rounding = result.wire_rounding
    assert rounding is not None and "rounded together" in result.status
    assert set(rounding.wires) == {"shoulder_spring", "forearm_spring", "elbow_spring"}
    sizes = np.array(PREFERRED_WIRE_DIAMETERS)
    for continuous, standard in rounding.wires.values():
        assert np.min(np.abs(sizes - standard)) < 1e-12
        below, above = sizes[sizes <= continuous], sizes[sizes >= continuous]
        assert standard in {float(below.max()), float(above.min())}
    before = result.metrics()["objectives"]["rms"]["before"]
    assert rounding.objective - rounding.continuous_objective <= standard_wire.JOINT_ACCEPT * (
        before - rounding.continuous_objective
    )
    assert result.evaluation.max_violation <= 1e-6


def test_the_joint_rounding_starts_from_each_wire_moved_alone():
    """The sets of wires the joint rounding starts from: every coil at its nearest size, every coil at its other
    neighbour, and each coil alone at its other one; a coil with one neighbour adds no set twice, and a coil whose
    wire is a standard size already (within AT_SIZE) is not moved alone."""
    sets = standard_wire._combinations([[2.2, 2.5], [4.0, 4.5], [3.0, 3.0]], [2.3, 4.2, 3.0])
    assert sets == [[2.2, 4.0, 3.0], [2.5, 4.5, 3.0], [2.5, 4.0, 3.0], [2.2, 4.5, 3.0]]
    at_size = 6.5 * (1 - 0.5 * standard_wire.AT_SIZE)
    sets = standard_wire._combinations([[6.5, 6.0], [2.8, 3.0]], [at_size, 2.89])
    assert sets == [[6.5, 2.8], [6.0, 3.0], [6.5, 3.0]]


def test_the_joint_rounding_keeps_the_best_set_of_wires(monkeypatch):
    """The demo's three coils, the joint rounding's solve scripted to return each start as it was given (every
    wire held, nothing re-optimised): the design kept is the set of standard wires of lowest objective, whichever
    start it was, and the record names its wires."""
    result = solve(load_config("examples/two_link.yaml"), progress=False, standard_wire=False)
    problem = result.problem
    given: list[np.ndarray] = []

    def scripted(problem, starts, initial, **options):
        given.append(np.array(initial))
        records = [
            StartRecord(i, x, x, float(problem.objective_value(problem.evaluate(x))), 0.0, "scripted", 1, 0.0)
            for i, x in enumerate(np.array(initial))
        ]
        return standard_wire.Solution(records[0].x, records, "auto", 0, "scripted")

    monkeypatch.setattr(standard_wire, "solve_problem", scripted)
    continuous = standard_wire.Solution(result.x, result.starts, "auto", 0, result.status)
    solution, rounding = standard_wire.round_wires(problem, continuous)
    starts = given[0]
    assert len(given) == 1 and 3 <= len(starts) <= 5  # nearest, other, and the single moves that differ
    objectives = [float(problem.objective_value(problem.evaluate(x))) for x in starts]
    best = starts[int(np.argmin(objectives))]
    np.testing.assert_array_equal(solution.x, best)
    assert rounding.objective == pytest.approx(min(objectives), rel=1e-12)
    names = problem.variables.names
    for spring, (_, standard) in rounding.wires.items():
        assert standard == best[names.index(f"{spring}.{standard_wire.WIRE}")]


def test_the_joint_rounding_keeps_a_set_that_makes_no_weighted_joint_worse(monkeypatch):
    """As above, with the set of lowest objective taken to carry a weighted joint worse than the bare arm: the
    rounding keeps the best of the others."""
    result = solve(load_config("examples/two_link.yaml"), progress=False, standard_wire=False)
    problem = result.problem

    def scripted(problem, starts, initial, **options):
        records = [
            StartRecord(i, x, x, float(problem.objective_value(problem.evaluate(x))), 0.0, "scripted", 1, 0.0)
            for i, x in enumerate(np.array(initial))
        ]
        scripted.objectives = [record.objective for record in records]
        return standard_wire.Solution(records[0].x, records, "auto", 0, "scripted")

    def refused(problem, design):
        return float(problem.objective_value(problem.evaluate(design))) == min(scripted.objectives)

    monkeypatch.setattr(standard_wire, "solve_problem", scripted)
    monkeypatch.setattr(standard_wire, "_refused", refused)
    continuous = standard_wire.Solution(result.x, result.starts, "auto", 0, result.status)
    solution, rounding = standard_wire.round_wires(problem, continuous)
    assert rounding.objective == pytest.approx(sorted(scripted.objectives)[1], rel=1e-12)
    assert rounding.objective > min(scripted.objectives)


def test_a_start_where_a_spring_has_zero_length_is_skipped_not_a_crash():
    """Both anchor boxes centred on the shoulder pivot (the ground's origin and link1's): at the first start
    (the boxes' midpoints) the spring has zero length in every pose and no direction, so the design has no
    value there. That start is reported as not run; the other starts solve. With that start alone the solve
    fails with a message that says why (this was a LinAlgError traceback on the Panda, link1 → link2)."""
    import pytest

    import springbalance as sb
    from springbalance.errors import SolverError

    mechanism = sb.Mechanism.from_urdf("urdf/two_link_planar.urdf")
    workspace = sb.Workspace.sobol(mechanism, n=64, seed=0)
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.1, 0, -0.1], [0.1, 0, 0.1])),
        sb.Anchor("link1", sb.Free([-0.1, 0, -0.1], [0.1, 0, 0.1])),
        name="s1",
        stiffness=sb.Free(0, 5000),
        free_length=sb.Free(0.0, 0.5),
        keep_tension=False,
    )
    problem = sb.DesignProblem(mechanism, workspace, [spring])
    result = solve(problem, starts=3, seed=0, progress=False, verify="off")
    assert result.starts[0].status == multistart.NOT_FINITE and not result.starts[0].feasible
    assert np.isfinite(result.evaluation.tau).all()
    with pytest.raises(SolverError, match="anchors coincide"):
        solve(problem, starts=1, seed=0, progress=False, verify="off")


def test_the_twin_cannot_ask_a_coil_for_more_force_than_any_coil_in_its_envelope_carries():
    """A coil of music wire in a 20 mm envelope (index 4–12): the strongest is the thickest wire whose coil
    fits at the smallest index, (4 + 1) d ≤ 20 mm: d = 4 mm, D = 16 mm. Its body carries
    F = τ_a π d² / (8 K_B C) with K_B(4) = 18/13 (Bergsträsser) and τ_a = 98 % · 45 % · S_ut, S_ut = 2211 MPa ·
    (d / 1 mm)^-0.145 (Shigley Tables 10-4 and 10-7; 2 % kept in reserve): the twin's max_force."""
    import springbalance as sb
    from springbalance.springs.laws.helical_extension import HelicalExtensionSpring

    coil = HelicalExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.2]), sb.Anchor("link1", [0.3, 0, 0]), "c", max_outer_diameter=0.02
    )
    strength = 2211e6 * 4.0**-0.145  # [Pa]
    expected = 0.98 * 0.45 * strength * np.pi * 0.004**2 / (8 * (18 / 13) * 4)  # [N], about 1.07 kN
    assert coil_start._largest_force(coil) == pytest.approx(expected, rel=1e-9)
    twin = coil_start._twin(coil)
    assert twin.max_force == pytest.approx(expected, rel=1e-9)


def test_the_ideal_twin_is_not_solved_again_when_no_cap_binds(monkeypatch):
    """The demo's capped twin balances exactly with every force far below its cap (a 40 mm coil carries
    about 2.2 kN; the demo's springs at most 1.6 kN): the uncapped problem has the same optimum, so the record
    is that optimum's and no second multi-start runs. The record still removes the whole rms torque."""
    problem = _demo()
    calls = []
    solve_problem = coil_start.solve_problem

    def counted(*args, **kwargs):
        calls.append(args[0])
        return solve_problem(*args, **kwargs)

    monkeypatch.setattr(coil_start, "solve_problem", counted)
    found = coil_start.coil_starts(problem, 3, starts=4, seed=0, method="auto", max_iterations=100, tolerance=1e-8)
    assert found is not None and len(calls) == 1  # the capped twin's multi-start alone
    assert not coil_start._cap_binds(found.twin, found.twin_x)
    record = found.record
    assert record.objective <= 1e-9 * record.objective_before
    assert all(cut > 99.99 for cut in record.joints.values()) and len(record.joints) == 2


def test_a_binding_cap_means_the_uncapped_twin_is_solved():
    """At a design where a twin's force reaches its cap, the cap binds (the record needs its own solve)."""
    problem = _demo()
    coils = coil_start.coil_springs(problem)
    twin = coil_start._twin_problem(problem, coils)
    x = np.asarray(twin.variables.start, dtype=float)
    forces = np.max(np.abs(twin.evaluate(x).tensions), axis=0)
    assert not coil_start._cap_binds(twin.with_springs([_capped(s, 10 * f) for s, f in zip(twin.springs, forces)]), x)
    assert coil_start._cap_binds(twin.with_springs([_capped(s, f) for s, f in zip(twin.springs, forces)]), x)


def _capped(spring, force):
    capped = copy.copy(spring)
    capped.max_force = float(force)
    return capped
