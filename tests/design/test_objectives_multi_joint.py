"""Objectives for several joints (joint_peaks, peak_then_joints) and the no_joint_worse constraint."""

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.objectives import JointPeaks, Peak, PeakThenJoints
from springbalance.design.problem_inputs import JOINT_LIMIT_FLOOR
from springbalance.design.problem_inputs import joint_limits as _joint_limits
from two_link_helpers import URDF, spring_per_joint

TOLERANCE = 1e-6  # relative


def _peaks(result) -> np.ndarray:
    """Each joint's weighted peak max_i |w_j tau_ij| [N·m·w] of a result."""
    return np.max(np.abs(result.evaluation.tau * result.problem.weights), axis=0)


@pytest.fixture(scope="module")
def arm():
    """The two-link arm over shoulder ±90°, elbow ±45°, with weights 1/(unbalanced peak) per joint.

    One extension spring ground → link1 (shoulder only) and one link1 → link2 (elbow only): the elbow
    spring sees only the elbow angle while the elbow's gravity torque depends on the shoulder angle
    too, so the elbow cannot be balanced; it decides the worst joint, and the shoulder is left over.
    """
    mechanism = sb.Mechanism.from_urdf(URDF)
    workspace = sb.Workspace.grid(mechanism, n=9, ranges={"shoulder": [-90, 90], "elbow": [-45, 45]}, degrees=True)
    unbalanced = np.max(np.abs(workspace.kinematics().gravity_torque), axis=0)
    weights = {joint: 1.0 / peak for joint, peak in zip(mechanism.joint_names, unbalanced)}
    springs = spring_per_joint()
    results = {
        objective: sb.solve(
            sb.DesignProblem(mechanism, workspace, springs, objective=objective, weights=weights), starts=3
        )
        for objective in ("peak", "peak_then_joints", "joint_peaks")
    }
    return mechanism, workspace, springs, weights, results


def test_values_follow_the_definitions():
    weighted = np.array([[1.0, -0.5], [-3.0, 0.25], [2.0, 0.75]])
    assert Peak().value(weighted, None, None) == 3.0
    assert JointPeaks().value(weighted, None, None) == 3.0 + 0.75
    assert PeakThenJoints().value(weighted, None, None) == 3.0  # the worst joint first,
    assert PeakThenJoints().tiebreak(weighted, None, None) == 3.0 + 0.75  # then the sum of the peaks
    assert {"joint_peaks", "peak_then_joints"} <= set(sb.OBJECTIVES)
    with pytest.raises(sb.InputError, match="slack"):
        PeakThenJoints(slack=-1)


def test_peak_then_joints_keeps_the_worst_joint_and_lowers_the_others(arm):
    *_, results = arm
    peak, lexicographic = _peaks(results["peak"]), _peaks(results["peak_then_joints"])
    slack = PeakThenJoints().slack
    # the worst joint keeps the minimax optimum (to the slack) ...
    assert lexicographic.max() <= peak.max() * (1 + slack) + TOLERANCE * peak.max()
    assert lexicographic.max() >= peak.max() * (1 - slack)
    # ... and the other joint comes down: minimax alone leaves it where its solver stopped
    assert lexicographic.sum() < peak.sum() - 10 * slack * peak.max()
    assert results["peak_then_joints"].evaluation.max_violation == 0.0
    assert results["peak_then_joints"].metrics()["objectives"]["peak_then_joints"]["after"] == pytest.approx(
        lexicographic.max(), rel=1e-12
    )


def test_joint_peaks_has_the_lowest_sum_of_joint_peaks(arm):
    *_, results = arm
    sums = {name: _peaks(result).sum() for name, result in results.items()}
    assert sums["joint_peaks"] <= min(sums.values()) * (1 + TOLERANCE)
    assert results["joint_peaks"].metrics()["objectives"]["joint_peaks"]["after"] == pytest.approx(
        sums["joint_peaks"], rel=1e-12
    )


def test_joint_peaks_nlp_has_one_epigraph_variable_per_joint(arm):
    mechanism, workspace, springs, weights, _ = arm
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="joint_peaks", weights=weights)
    nlp = problem.build()
    assert nlp.size == nlp.n_design + mechanism.nv
    assert nlp.n_rows == problem.model.n_constraints * workspace.size + 2 * mechanism.nv * workspace.size
    with pytest.raises(sb.InputError, match="least_squares"):
        sb.solve(problem, starts=1, method="least_squares")


# ---------------------------------------------------------------------- no_joint_worse
@pytest.fixture(scope="module")
def crossing():
    """One spring from the ground to link2, across both joints, elbow ±90°: balancing the
    shoulder (weight 1) loads the elbow (weight 0.01), which ends up worse than without springs."""
    mechanism = sb.Mechanism.from_urdf(URDF)
    workspace = sb.Workspace.grid(mechanism, n=9, ranges={"shoulder": [-90, 90], "elbow": [-90, 90]}, degrees=True)
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.1, 0, 0.02], [0.1, 0, 0.4])),
        sb.Anchor("link2", sb.Free([-0.1, 0, -0.05], [0.3, 0, 0.05])),
        stiffness=sb.Free(0, 5000),
        free_length=sb.Free(0.0, 0.8),
    )
    unbalanced = np.max(np.abs(workspace.kinematics().gravity_torque), axis=0)
    return mechanism, workspace, [spring], {"shoulder": 1.0, "elbow": 0.01}, unbalanced


def test_without_the_constraint_a_joint_gets_worse(crossing):
    """The multi-start alone (before the pipeline holds the joints: tests/design/test_joint_hold.py)."""
    from springbalance.design.solvers import solve_problem

    mechanism, workspace, springs, weights, unbalanced = crossing
    problem = sb.DesignProblem(mechanism, workspace, springs, weights=weights)
    solution = solve_problem(problem, starts=2, progress=False)
    peaks = np.max(np.abs(problem.evaluate(solution.x).tau), axis=0)
    assert peaks[1] > 1.1 * unbalanced[1]


@pytest.mark.parametrize(
    "objective, method",
    [("rms", "least_squares"), ("rms", "ipopt"), ("rms", "auto"), ("peak", "auto"), ("peak_then_joints", "auto")],
)
def test_no_joint_worse_keeps_every_joint_within_its_unbalanced_peak(crossing, objective, method):
    mechanism, workspace, springs, weights, unbalanced = crossing
    problem = sb.DesignProblem(mechanism, workspace, springs, objective=objective, weights=weights, no_joint_worse=True)
    np.testing.assert_allclose(problem.joint_limits, unbalanced[None, :], rtol=1e-12)
    result = sb.solve(problem, starts=2, method=method)
    peaks = np.max(np.abs(result.evaluation.tau), axis=0)
    assert np.all(peaks <= unbalanced * (1 + TOLERANCE))
    assert peaks[0] < 0.5 * unbalanced[0]  # and the shoulder is still balanced in part
    assert result.evaluation.max_violation <= 1e-6


def test_no_joint_worse_rows_only_for_weighted_joints(crossing):
    mechanism, workspace, springs, _, unbalanced = crossing
    plain = sb.DesignProblem(mechanism, workspace, springs, weights={"elbow": 0})
    problem = sb.DesignProblem(mechanism, workspace, springs, weights={"elbow": 0}, no_joint_worse=True)
    names = [block.name for block in problem.model.constraint_blocks]
    assert names[plain.model.n_constraints :] == ["no_joint_worse.shoulder"]
    assert np.isnan(problem.joint_limits[0, 1])
    # rows (P² − tau²)/P at the design's start: ≥ 0 exactly where |tau| ≤ P
    evaluation = problem.evaluate()
    tau, rows = evaluation.tau[:, 0], evaluation.constraint_rows[:, -1]
    np.testing.assert_allclose(rows, (unbalanced[0] ** 2 - tau**2) / unbalanced[0], rtol=1e-9, atol=1e-9)
    assert problem.build().n_rows == plain.build().n_rows + workspace.size


def test_joint_limits_floor_a_joint_that_gravity_does_not_load():
    gravity = np.array([[3.0, 0.0, 1.0], [-5.0, 0.0, 0.5]])
    limits = _joint_limits(gravity, np.array([1.0, 1.0, 0.0]), 1)
    np.testing.assert_array_equal(limits[0, :2], [5.0, JOINT_LIMIT_FLOOR * 5.0])
    assert np.isnan(limits[0, 2])
    # per scenario block: each block's own peaks
    stacked = _joint_limits(np.vstack([gravity, 2 * gravity]), np.ones(3), 2)
    np.testing.assert_array_equal(stacked[:, 0], [5.0, 10.0])


def test_no_joint_worse_from_config_and_saved_design(crossing, tmp_path):
    from springbalance.io.config import config_from_dict

    record = {
        "mechanism": {"urdf": URDF},
        "workspace": {"kind": "grid", "n": 5, "degrees": True, "ranges": {"shoulder": [-90, 90], "elbow": [-90, 90]}},
        "springs": [
            {
                "type": "zero_free_length",
                "a": {"body": "universe", "box": {"lower": [-0.1, 0, 0.02], "upper": [0.1, 0, 0.4]}},
                "b": {"body": "link2", "box": {"lower": [-0.1, 0, -0.05], "upper": [0.3, 0, 0.05]}},
                "stiffness": {"lower": 0, "upper": 5000},
            }
        ],
        "objective": "peak_then_joints",
        "weights": {"shoulder": 1, "elbow": 0.01},
        "no_joint_worse": True,
        "solve": {"starts": 1},
    }
    config = config_from_dict(record)
    assert config.problem.no_joint_worse and config.problem.objective.name == "peak_then_joints"
    assert not config_from_dict({**record, "no_joint_worse": False}).problem.no_joint_worse
    with pytest.raises(sb.ConfigError, match="no_joint_worse"):
        config_from_dict({**record, "no_joint_worse": "yes"})
    result = config.solve()
    unbalanced = np.max(np.abs(config.workspace.kinematics().gravity_torque), axis=0)
    assert np.all(np.max(np.abs(result.evaluation.tau), axis=0) <= unbalanced * (1 + TOLERANCE))
    loaded = sb.DesignResult.load(result.save(tmp_path / "design.json"))
    assert loaded.problem.no_joint_worse and loaded.problem.objective.name == "peak_then_joints"
    np.testing.assert_array_equal(loaded.evaluation.constraint_rows, result.evaluation.constraint_rows)


# ---------------------------------------------------------------------- scenarios
def test_joint_peaks_worst_scenario_and_peak_then_joints_needs_sum(crossing):
    mechanism, workspace, springs, weights, _ = crossing
    scenarios = [sb.Scenario("bare"), sb.Scenario("tool", payloads=[sb.Payload("tool", 0.5)])]
    with pytest.raises(sb.InputError, match="aggregate 'sum'"):
        sb.DesignProblem(
            mechanism,
            workspace,
            springs,
            objective="peak_then_joints",
            weights=weights,
            scenarios=scenarios,
            aggregate="worst",
        )
    problem = sb.DesignProblem(
        mechanism, workspace, springs, objective="joint_peaks", weights=weights, scenarios=scenarios, aggregate="worst"
    )
    nlp = problem.build()
    assert nlp.size == nlp.n_design + 2 * mechanism.nv + 1  # t_sj per scenario and joint, and the worst
    result = sb.solve(problem, starts=1)
    blocks = np.split(result.evaluation.tau * problem.weights, 2)
    per_scenario = [JointPeaks().value(block, None, None) for block in blocks]
    assert result.metrics()["optimised"] == "joint_peaks"
    assert problem.objective_value(result.evaluation) == pytest.approx(max(per_scenario), rel=1e-12)
    assert max(per_scenario) < JointPeaks().value(
        problem.workspace.kinematics().gravity_torque * problem.weights, None, None
    )


def test_no_joint_worse_between_the_samples_holds_the_bare_arm_where_it_carries_more():
    """Between the samples the bare arm may pass its sampled peak ``P_j``: there the limit is its own torque
    ``|g_ij|``. The elbow, which the shoulder's spring does not act on (``tau = g``), then meets its row at every
    pose and the design is verified; with ``P_j`` alone it broke it wherever the bare elbow passed ``P_j``."""
    from springbalance.design.verification_refine import evaluated_at

    mechanism = sb.Mechanism.from_urdf(URDF)
    ranges = {"shoulder": [-90, 90], "elbow": [-90, 90]}
    workspace = sb.Workspace.sobol(mechanism, n=8, seed=1, ranges=ranges, degrees=True)
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.1, 0, 0.02], [0.1, 0, 0.3])),
        sb.Anchor("link1", sb.Free([0.05, 0, -0.05], [0.45, 0, 0.05])),
        stiffness=sb.Free(0, 5000),
        free_length=sb.Free(0.0, 0.5),
    )
    problem = sb.DesignProblem(mechanism, workspace, [spring], no_joint_worse=True)
    peak = problem.joint_limits[0]
    dense = sb.Workspace.grid(mechanism, n=41, ranges=ranges, degrees=True)
    bare = np.abs(dense.kinematics().gravity_torque)
    beyond = np.argmax(bare[:, 1])
    assert bare[beyond, 1] > 1.01 * peak[1]  # a pose where the bare elbow carries more than at any sample

    result = sb.solve(problem, starts=2)
    tau, _, rows = evaluated_at(problem, result.x, dense.joint_values)
    np.testing.assert_array_equal(tau[:, 1], dense.kinematics().gravity_torque[:, 1])  # the spring leaves the elbow
    limit = np.maximum(peak[None, :], bare)
    np.testing.assert_allclose(rows[:, -2:], (limit**2 - tau**2) / limit, rtol=1e-9, atol=1e-12)
    assert rows[beyond, -1] >= 0.0  # (P² − g²)/P < 0 there
    # at the samples the limit is P: the rows the solver saw
    at_samples = result.evaluation.constraint_rows[:, -2:]
    np.testing.assert_allclose(at_samples, (peak**2 - result.evaluation.tau**2) / peak, rtol=1e-9, atol=1e-12)
    elbow = next(rule for rule in result.verification.rules if rule.rule == "no_joint_worse.elbow")
    assert elbow.passed and result.verification.passed


@pytest.mark.parametrize("objective", ["rms", "peak", "joint_peaks"])
def test_objective_at_a_design_is_the_objective_of_its_weighted_residual_torques(arm, objective):
    """``DesignProblem.objective_at(x)``: the objective over the samples of ``x``'s weighted torques, as written out
    from the residual ``tau`` (the weighted RMS, the largest |w τ|, the sum of the per-joint peaks)."""
    mechanism, workspace, springs, weights, _ = arm
    problem = sb.DesignProblem(mechanism, workspace, springs, objective=objective, weights=weights)
    x = 0.5 * np.add(*problem.variables.bounds())  # the boxes' centres
    weighted = problem.evaluate(x).tau * problem.weights
    expected = {
        "rms": float(np.sqrt(np.mean(weighted**2))),
        "peak": float(np.max(np.abs(weighted))),
        "joint_peaks": float(np.sum(np.max(np.abs(weighted), axis=0))),
    }[objective]
    assert problem.objective_at(x) == pytest.approx(expected, rel=1e-12)
    assert problem.objective_at(list(x)) == problem.objective_at(x)  # any array-like design
