"""The solvers: constraints honoured, every objective, determinism, failures reported."""

import numpy as np
import pytest

import springbalance as sb

G = 9.8


@pytest.fixture(scope="module")
def link():
    mechanism = sb.Mechanism.from_urdf("urdf/single_link_r2.urdf", gravity=G)
    return mechanism, sb.Workspace.grid(mechanism, 181)


@pytest.fixture(scope="module")
def arm():
    mechanism = sb.Mechanism.from_urdf("urdf/two_link_planar.urdf")
    return mechanism, sb.Workspace.sobol(mechanism, 256, seed=3)


def test_max_stretch_and_max_force_hold_at_the_solution(link):
    mechanism, workspace = link
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.1]),
        sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.4, 0, 0])),
        stiffness=sb.Free(0, 2000),
        free_length=sb.Free(0.02, 0.5),
        max_stretch=2.5,
        max_force=30.0,
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=4)
    lengths, tensions = result.evaluation.lengths[:, 0], result.evaluation.tensions[:, 0]
    l0 = result.variables["s1.free_length"]
    assert np.all(lengths >= l0 - 1e-6)  # stays in tension
    assert np.all(lengths <= 2.5 * l0 + 1e-6)  # stretch limit
    assert np.max(np.abs(tensions)) <= 30.0 + 1e-4  # force limit
    # the limits bind: without them the same spring does better
    free = sb.ExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.1]),
        sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.4, 0, 0])),
        stiffness=sb.Free(0, 2000),
        free_length=sb.Free(0.02, 0.5),
    )
    unconstrained = sb.solve(sb.DesignProblem(mechanism, workspace, [free]), starts=4)
    assert unconstrained.metrics()["objectives"]["rms"]["after"] < result.metrics()["objectives"]["rms"]["after"]


def test_energy_objective_on_an_ordered_path(link):
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.2, 0, 0]), stiffness=sb.Free(0, 500)
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring], objective="energy"), starts=2)
    # exact balance exists (k = m g c / (a b) = 122.5 N/m), so the path work goes to ~0
    assert result.variables["s1.stiffness"] == pytest.approx(1.0 * G * 0.25 / (0.1 * 0.2), rel=1e-3)
    energy = result.metrics()["objectives"]["energy"]
    assert energy["before"] == pytest.approx(4 * 1.0 * G * 0.25, rel=1e-3)  # ∫|m g c cos θ| dθ over a turn
    assert energy["after"] < 1e-3 * energy["before"]


def test_energy_needs_an_ordered_workspace(arm):
    mechanism, workspace = arm
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.2, 0, 0]), stiffness=sb.Free(0, 500)
    )
    with pytest.raises(sb.InputError, match="ordered"):
        sb.DesignProblem(mechanism, workspace, [spring], objective="energy")


def test_segment_and_plane_anchors_are_optimised(arm):
    mechanism, workspace = arm
    springs = [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Plane([0, 0, 0], [1, 0, 0], [0, 0, 1], [-0.1, 0.0], [0.1, 0.3])),
            sb.Anchor("link1", sb.Segment([0.05, 0, 0], [0.5, 0, 0])),
            stiffness=sb.Free(0, 3000),
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", sb.Free([-0.2, 0, 0.0], [0.2, 0, 0.6])),
            sb.Anchor("link2", sb.Segment([0.0, 0, 0], [0.4, 0, 0])),
            stiffness=sb.Free(0, 3000),
        ),
        # link1 → link2 cancels the cross term e1·e2 that the ground → link2 spring adds (docs/model.md §9)
        sb.ZeroFreeLengthSpring(
            sb.Anchor("link1", [0.25, 0, 0]),
            sb.Anchor("link2", sb.Free([-0.2, 0, 0], [0.4, 0, 0])),
            stiffness=sb.Free(0, 3000),
        ),
    ]
    result = sb.solve(sb.DesignProblem(mechanism, workspace, springs), starts=6)
    rms = result.metrics()["objectives"]["rms"]
    assert rms["after"] < 1e-9 * rms["before"]  # exact balance exists for this topology
    anchor = np.array(result.spring("s1")["b"]["point"])
    assert 0.05 - 1e-12 <= anchor[0] <= 0.5 + 1e-12 and anchor[1] == 0 and anchor[2] == 0
    ground = np.array(result.spring("s1")["a"]["point"])
    assert ground[1] == pytest.approx(0.0, abs=1e-12)  # stays in its plane


def test_multistart_is_deterministic_given_a_seed(arm):
    mechanism, workspace = arm

    def solve(seed):
        spring = sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free([-0.1, 0, 0], [0.1, 0, 0.4])),
            sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.5, 0, 0])),
            stiffness=sb.Free(0, 3000),
            free_length=sb.Free(0.02, 0.5),
        )
        return sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=3, seed=seed)

    first, again, other = solve(7), solve(7), solve(8)
    assert np.array_equal(first.x, again.x)
    assert [r.objective for r in first.starts] == [r.objective for r in again.starts]
    assert [r.objective for r in first.starts] != [r.objective for r in other.starts]
    assert first.spread()["starts"] == 3


@pytest.mark.parametrize("method", ["least_squares", "ipopt", "auto"])
def test_every_method_balances_a_link(link, method):
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.2, 0, 0]), stiffness=sb.Free(0, 500)
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=1, method=method)
    assert result.variables["s1.stiffness"] == pytest.approx(122.5, rel=1e-6)
    assert result.status.startswith(method if method != "auto" else "least_squares")


def test_least_squares_refuses_a_minimax_objective(link):
    mechanism, workspace = link
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.2, 0, 0]), stiffness=sb.Free(0, 500)
    )
    with pytest.raises(sb.InputError, match="peak"):
        sb.solve(sb.DesignProblem(mechanism, workspace, [spring], objective="peak"), method="least_squares")


def test_infeasible_design_raises_solver_error_with_statuses(link):
    mechanism, workspace = link
    # the spring is at most 0.3 m long, but its free length must be at least 0.35 m: it can never stay in tension
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.1]),
        sb.Anchor("link1", [0.2, 0, 0]),
        stiffness=sb.Free(0, 500),
        free_length=sb.Free(0.35, 0.5),
    )
    with pytest.raises(sb.SolverError) as caught:
        sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=2)
    assert "start 0" in str(caught.value) and "violation" in str(caught.value)
    assert len(caught.value.starts) == 2 and caught.value.problem is not None
    assert all(record.max_violation > 0.04 for record in caught.value.starts)


def test_build_exposes_the_nlp(arm):
    mechanism, workspace = arm
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", [0, 0, 0.1]),
        sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.5, 0, 0])),
        stiffness=sb.Free(0, 3000),
        free_length=sb.Free(0.02, 0.5),
    )
    problem = sb.DesignProblem(mechanism, workspace, [spring], objective="peak")
    nlp = problem.build()
    assert problem.variables.names == ["s1.b.x", "s1.stiffness", "s1.free_length"]
    assert nlp.n_design == 3 and nlp.size == 4  # + the epigraph variable
    assert nlp.n_rows == workspace.size * (1 + 2 * mechanism.nv)  # tension rows + |tau| ≤ t rows
