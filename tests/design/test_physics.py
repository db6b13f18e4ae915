"""The residual torque is the gradient of the total potential (docs/model.md §2–4).

Each test builds springs through the public API, evaluates the library's residual
torque, and compares it with an independent computation: Pinocchio's potential energy
plus each spring's potential (anchor positions from ``framesForwardKinematics``),
differentiated by finite differences (``physics_helpers.ReferencePotential``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from physics_helpers import ReferencePotential, RefSpring

URDF = Path(__file__).resolve().parents[2] / "urdf"

#: (body a, body b) of the four UR5 springs of the brief.
UR5_PAIRS = [
    ("universe", "upper_arm_link"),
    ("universe", "forearm_link"),
    ("upper_arm_link", "forearm_link"),
    ("shoulder_link", "forearm_link"),
]

RELATIVE = 1e-6


@pytest.fixture(scope="module")
def ur5():
    return sb.Mechanism.from_robot("ur5")


def _random_ur5_workspace(mechanism, rng, n=20):
    values = rng.uniform(-np.pi, np.pi, size=(n, mechanism.nv))
    return sb.Workspace.from_array(mechanism, values, ordered=False)


def _random_point(rng, body):
    if body == "universe":
        return rng.uniform([-0.4, -0.4, 0.0], [0.4, 0.4, 0.8])
    return rng.uniform(-0.25, 0.25, size=3)


def _assert_torque_is_potential_gradient(mechanism, workspace, tau, reference, potential=None):
    """Library torque (N×nv) against the finite-difference gradient of the reference potential."""
    assert tau.shape == (workspace.size, mechanism.nv)
    for i, q in enumerate(workspace.configurations):
        expected = reference.torque(q)
        scale = max(np.max(np.abs(expected)), 1.0)
        np.testing.assert_allclose(
            tau[i], expected, rtol=0, atol=RELATIVE * scale, err_msg=f"sample {i}, q = {workspace.joint_values[i]}"
        )
        if potential is not None:
            v = reference(q)
            assert abs(potential[i] - v) <= 1e-10 * max(abs(v), 1.0), (i, potential[i], v)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_ur5_extension_springs_match_potential_gradient(ur5, seed):
    rng = np.random.default_rng(seed)
    workspace = _random_ur5_workspace(ur5, rng)
    springs, reference_springs = [], []
    for a, b in UR5_PAIRS:
        pa, pb = _random_point(rng, a), _random_point(rng, b)
        k, l0, f0 = rng.uniform(100, 5000), rng.uniform(0.05, 0.5), rng.uniform(0, 50)
        springs.append(
            sb.ExtensionSpring(
                sb.Anchor(a, pa), sb.Anchor(b, pb), stiffness=k, free_length=l0, initial_tension=f0, keep_tension=False
            )
        )
        reference_springs.append(RefSpring(a, tuple(pa), b, tuple(pb), k, l0, f0))
    problem = sb.DesignProblem(ur5, workspace, springs)
    assert problem.variables.size == 0
    evaluation = problem.evaluate(np.zeros(0))
    reference = ReferencePotential(ur5.model, reference_springs)
    _assert_torque_is_potential_gradient(ur5, workspace, evaluation.tau, reference, evaluation.potential)
    # The result object reports the same torque.
    np.testing.assert_array_equal(sb.DesignResult(problem, np.zeros(0)).residual_torque(), evaluation.tau)
    # Spring lengths are the anchor distances.
    for i, q in enumerate(workspace.configurations):
        np.testing.assert_allclose(evaluation.lengths[i], reference.lengths(q), rtol=1e-12, atol=1e-12)
    # Tension F = F0 + k (L - l0) (docs/model.md §3.1).
    k = np.array([s.stiffness for s in reference_springs])
    l0 = np.array([s.free_length for s in reference_springs])
    f0 = np.array([s.initial_tension for s in reference_springs])
    np.testing.assert_allclose(evaluation.tensions, f0 + k * (evaluation.lengths - l0), rtol=1e-12, atol=1e-9)
    # The springs change the torque: the test would notice a library that ignored them.
    gravity_only = ReferencePotential(ur5.model, [])
    q0 = workspace.configurations[0]
    assert np.max(np.abs(evaluation.tau[0] - gravity_only.torque(q0))) > 1.0


@pytest.mark.parametrize("seed", [3, 4])
def test_ur5_zero_free_length_springs_match_potential_gradient(ur5, seed):
    rng = np.random.default_rng(seed)
    workspace = _random_ur5_workspace(ur5, rng)
    springs, reference_springs = [], []
    for a, b in UR5_PAIRS:
        pa, pb = _random_point(rng, a), _random_point(rng, b)
        k = rng.uniform(100, 5000)
        springs.append(sb.ZeroFreeLengthSpring(sb.Anchor(a, pa), sb.Anchor(b, pb), stiffness=k))
        reference_springs.append(RefSpring(a, tuple(pa), b, tuple(pb), k, zero_free_length=True))
    problem = sb.DesignProblem(ur5, workspace, springs)
    tau = sb.DesignResult(problem, np.zeros(0)).residual_torque()
    reference = ReferencePotential(ur5.model, reference_springs)
    _assert_torque_is_potential_gradient(ur5, workspace, tau, reference, problem.evaluate(np.zeros(0)).potential)
    np.testing.assert_allclose(
        problem.evaluate(np.zeros(0)).tensions,
        np.array([s.stiffness for s in reference_springs]) * problem.evaluate(np.zeros(0)).lengths,
        rtol=1e-12,
    )


@pytest.mark.parametrize("seed", [5, 6])
def test_ur5_free_design_at_random_x_matches_potential_gradient(ur5, seed):
    """Free anchors (box, segment, plane) and free parameters, evaluated at a random x in the bounds."""
    rng = np.random.default_rng(seed)
    workspace = _random_ur5_workspace(ur5, rng)
    box_lower, box_upper = np.array([-0.2, -0.1, 0.3]), np.array([0.2, 0.1, 0.6])
    seg_start, seg_end = np.array([0.0, 0.0, 0.05]), np.array([0.0, 0.1, 0.4])
    plane_origin, plane_u, plane_v = np.array([0.05, 0.0, 0.0]), np.array([2.0, 0.0, 0.0]), np.array([0.0, 0.0, 3.0])
    springs = [
        sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free(box_lower, box_upper)),
            sb.Anchor("upper_arm_link", sb.Segment(seg_start, seg_end)),
            name="ext",
            stiffness=sb.Free(100, 3000),
            free_length=sb.Free(0.05, 0.4),
            initial_tension=sb.Free(0, 40),
            keep_tension=False,
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("shoulder_link", sb.Plane(plane_origin, plane_u, plane_v, [-0.1, -0.1], [0.1, 0.2])),
            sb.Anchor("forearm_link", (0.0, 0.02, 0.2)),
            name="zfl",
            stiffness=sb.Free(50, 2000),
        ),
    ]
    problem = sb.DesignProblem(ur5, workspace, springs)
    chosen = {
        "ext.a.x": rng.uniform(-0.2, 0.2),
        "ext.a.y": rng.uniform(-0.1, 0.1),
        "ext.a.z": rng.uniform(0.3, 0.6),
        "ext.b.s": rng.uniform(0, 1),
        "ext.stiffness": rng.uniform(100, 3000),
        "ext.free_length": rng.uniform(0.05, 0.4),
        "ext.initial_tension": rng.uniform(0, 40),
        "zfl.a.u": rng.uniform(-0.1, 0.1),
        "zfl.a.v": rng.uniform(-0.1, 0.2),
        "zfl.stiffness": rng.uniform(50, 2000),
    }
    assert sorted(problem.variables.names) == sorted(chosen)
    x = np.array([chosen[name] for name in problem.variables.names])
    lower, upper = problem.variables.bounds()
    assert np.all(lower <= x) and np.all(x <= upper)

    point_a = np.array([chosen["ext.a.x"], chosen["ext.a.y"], chosen["ext.a.z"]])
    point_b = seg_start + chosen["ext.b.s"] * (seg_end - seg_start)
    plane_point = (
        plane_origin
        + chosen["zfl.a.u"] * plane_u / np.linalg.norm(plane_u)
        + chosen["zfl.a.v"] * plane_v / np.linalg.norm(plane_v)
    )
    reference = ReferencePotential(
        ur5.model,
        [
            RefSpring(
                "universe",
                tuple(point_a),
                "upper_arm_link",
                tuple(point_b),
                chosen["ext.stiffness"],
                chosen["ext.free_length"],
                chosen["ext.initial_tension"],
            ),
            RefSpring(
                "shoulder_link",
                tuple(plane_point),
                "forearm_link",
                (0.0, 0.02, 0.2),
                chosen["zfl.stiffness"],
                zero_free_length=True,
            ),
        ],
    )
    evaluation = problem.evaluate(x)
    _assert_torque_is_potential_gradient(ur5, workspace, evaluation.tau, reference, evaluation.potential)
    result = sb.DesignResult(problem, x)
    np.testing.assert_array_equal(result.residual_torque(), evaluation.tau)
    # The result reports the anchors and parameters that were evaluated.
    np.testing.assert_allclose(result.spring("ext")["a"]["point"], point_a, rtol=0, atol=1e-15)
    np.testing.assert_allclose(result.spring("ext")["b"]["point"], point_b, rtol=0, atol=1e-15)
    np.testing.assert_allclose(result.spring("zfl")["a"]["point"], plane_point, rtol=0, atol=1e-15)
    assert result.spring("ext")["stiffness"] == chosen["ext.stiffness"]
    # Re-evaluating the fixed design on other configurations gives the same physics.
    others = rng.uniform(-np.pi, np.pi, size=(5, ur5.nv))
    tau_others = result.residual_torque(others)
    other_workspace = sb.Workspace.from_array(ur5, others)
    _assert_torque_is_potential_gradient(ur5, other_workspace, tau_others, reference)


# ---------------------------------------------------------------------- exact balance (docs/model.md §9)
R2_MASS, R2_COM, R2_GRAVITY = 1.0, 0.25, 9.8


@pytest.fixture(scope="module")
def r2():
    return sb.Mechanism.from_urdf(URDF / "single_link_r2.urdf", gravity=R2_GRAVITY)


@pytest.mark.parametrize("a, b", [(0.1, 0.2), (0.04, 0.37)])
def test_zero_free_length_spring_balances_single_link_exactly(r2, a, b):
    """k a b = m g c makes the total potential constant: zero torque at every angle."""
    stiffness = R2_MASS * R2_GRAVITY * R2_COM / (a * b)
    workspace = sb.Workspace.grid(r2, 2001)  # every 0.18° of the full turn
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, a)), sb.Anchor("link1", (b, 0, 0)), stiffness=stiffness
    )
    problem = sb.DesignProblem(r2, workspace, [spring])
    evaluation = problem.evaluate(np.zeros(0))
    assert np.max(np.abs(evaluation.tau)) < 1e-9
    assert np.ptp(evaluation.potential) < 1e-9
    # The mechanism was not trivially balanced: gravity alone needs m g c = 2.45 N·m.
    assert np.max(np.abs(workspace.kinematics().gravity_torque)) == pytest.approx(
        R2_MASS * R2_GRAVITY * R2_COM, rel=1e-9
    )
    # A 1 % stiffer spring is no longer a balance: residual (0.01 k a b) cos q.
    off = sb.DesignProblem(r2, workspace, [sb.ZeroFreeLengthSpring(spring.a, spring.b, stiffness=1.01 * stiffness)])
    theta = workspace.joint_values[:, 0]
    np.testing.assert_allclose(
        off.evaluate(np.zeros(0)).tau[:, 0], -0.01 * R2_MASS * R2_GRAVITY * R2_COM * np.cos(theta), rtol=0, atol=1e-9
    )


def test_gravity_torque_sign_and_spring_pulling_up_reduces_it(r2):
    """Link horizontal: gravity pulls the tip down, the holding torque is +m g c (counter-clockwise)."""
    workspace = sb.Workspace.from_array(r2, [[0.0], [np.pi / 6], [-np.pi / 4]])
    gravity = R2_MASS * R2_GRAVITY * R2_COM * np.cos(workspace.joint_values[:, 0])  # ∂(m g c sin q)/∂q
    np.testing.assert_allclose(workspace.kinematics().gravity_torque[:, 0], gravity, rtol=1e-12)
    # Extension spring from above the pivot to the link: pulls the link up.
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", (0, 0, 0.1)),
        sb.Anchor("link1", (0.2, 0, 0)),
        stiffness=100.0,
        free_length=0.05,
        keep_tension=False,
    )
    tau = sb.DesignProblem(r2, workspace, [spring]).evaluate(np.zeros(0)).tau[:, 0]
    # Independent: L² = a² + b² - 2ab sin q, dL/dq = -ab cos q / L, tau = g + k (L - l0) dL/dq.
    theta = workspace.joint_values[:, 0]
    length = np.sqrt(0.1**2 + 0.2**2 - 2 * 0.1 * 0.2 * np.sin(theta))
    expected = gravity + 100.0 * (length - 0.05) * (-0.1 * 0.2 * np.cos(theta) / length)
    np.testing.assert_allclose(tau, expected, rtol=1e-12)
    assert np.all(np.abs(tau) < np.abs(gravity))
    assert tau[0] > 0  # reduced, not overturned (spring moment 1.53 N·m < 2.45 N·m)
    # The same spring below the pivot pulls the link down and increases the torque.
    below = sb.ExtensionSpring(
        sb.Anchor("universe", (0, 0, -0.1)),
        sb.Anchor("link1", (0.2, 0, 0)),
        stiffness=100.0,
        free_length=0.05,
        keep_tension=False,
    )
    tau_below = sb.DesignProblem(r2, workspace, [below]).evaluate(np.zeros(0)).tau[:, 0]
    assert np.all(np.abs(tau_below) > np.abs(gravity))


def test_ur5_spring_on_link_welded_to_ground(ur5):
    """UR5's link "base" is welded to the ground rotated by π about z: the anchor turns with it."""
    rng = np.random.default_rng(8)
    workspace = _random_ur5_workspace(ur5, rng, n=10)
    point_a, point_b = (0.15, 0.05, 0.3), (0.02, 0.1, 0.25)
    spring = sb.ExtensionSpring(
        sb.Anchor("base", point_a),
        sb.Anchor("upper_arm_link", point_b),
        stiffness=800.0,
        free_length=0.1,
        initial_tension=10.0,
        keep_tension=False,
    )
    evaluation = sb.DesignProblem(ur5, workspace, [spring]).evaluate(np.zeros(0))
    reference = ReferencePotential(ur5.model, [RefSpring("base", point_a, "upper_arm_link", point_b, 800.0, 0.1, 10.0)])
    _assert_torque_is_potential_gradient(ur5, workspace, evaluation.tau, reference, evaluation.potential)
