"""A spring's own mass (docs/model.md §5): half at each end, fixed or coupled to k via the coil.

The total potential now holds ``-(m_s/2) g·(x_a + x_b)`` per spring and the holding torque
``-(m_s/2)(J_pa + J_pb)^T g``; both are checked against the finite-difference gradient of the
independent reference potential, and against the closed form of a single link.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from physics_helpers import ReferencePotential, RefSpring

URDF = Path(__file__).resolve().parents[2] / "urdf"


def coil_mass(k, D, n, wire_length, G, rho):
    """m_s = rho π L_w sqrt(D³ n k / (2 G)) (docs/model.md §5), from k = G d⁴/(8 D³ n) and m = rho L_w π d²/4."""
    d = (8 * D**3 * n * k / G) ** 0.25
    return rho * wire_length * np.pi * d**2 / 4


def test_coil_mass_formula_matches_wire_volume():
    coil = sb.CoilMass(coil_diameter=0.04, active_coils=80, wire_length=10.38, shear_modulus=81e9, density=7800)
    for k in (1.0, 324.0, 5000.0):
        assert coil.value({"stiffness": k}) == pytest.approx(coil_mass(k, 0.04, 80, 10.38, 81e9, 7800), rel=1e-12)
    # material defaults (music wire: G 81.0 GPa, 7800 kg/m³) and the default wire length π D (n + 2)
    from_material = sb.CoilMass(coil_diameter=0.04, active_coils=80, material="music_wire")
    assert from_material.wire_length == pytest.approx(np.pi * 0.04 * 82)
    assert from_material.value({"stiffness": 324.0}) == pytest.approx(
        coil_mass(324.0, 0.04, 80, np.pi * 0.04 * 82, 81.0e9, 7800.0), rel=1e-12
    )


def test_half_mass_at_each_end_of_a_single_link():
    """R1 link, weightless-k spring with mass m from B above the pivot to A at r on the link:
    its holding torque is the weight of m/2 at r, -(m/2) g r sin(phi), beside the link's own
    -m1 g s1 sin(phi) (the B half hangs on the ground)."""
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 37, ranges={"pivot": (-np.pi, np.pi)})
    phi = workspace.joint_values[:, 0]
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.16)), sb.Anchor("link1", (0, 0, 0.3)), stiffness=0.0, mass=0.5
    )
    evaluation = sb.DesignProblem(mechanism, workspace, [spring]).evaluate(np.zeros(0))
    g = 9.81
    np.testing.assert_allclose(evaluation.tau[:, 0], -(8.0 * 0.183 + 0.25 * 0.3) * g * np.sin(phi), atol=1e-12)
    # potential: link, then m/2 at A = (0, -0.3 sin phi, 0.3 cos phi) and m/2 at B = (0, 0, 0.16)
    np.testing.assert_allclose(
        evaluation.potential, g * (8.0 * 0.183 * np.cos(phi) + 0.25 * 0.3 * np.cos(phi) + 0.25 * 0.16), atol=1e-12
    )


@pytest.mark.parametrize("coupled", [False, True])
def test_spring_mass_on_ur5_matches_potential_gradient(coupled):
    ur5 = sb.Mechanism.from_robot("ur5")
    rng = np.random.default_rng(11)
    workspace = sb.Workspace.from_array(ur5, rng.uniform(-np.pi, np.pi, size=(10, ur5.nv)), ordered=False)
    pairs = [("universe", "upper_arm_link"), ("upper_arm_link", "forearm_link"), ("shoulder_link", "wrist_1_link")]
    springs, reference = [], []
    for index, (body_a, body_b) in enumerate(pairs):
        pa = rng.uniform([-0.3, -0.3, 0.0], [0.3, 0.3, 0.6]) if body_a == "universe" else rng.uniform(-0.2, 0.2, 3)
        pb = rng.uniform(-0.2, 0.2, 3)
        k, l0 = rng.uniform(200, 3000), rng.uniform(0.05, 0.4)
        if coupled:
            D, n, wire = rng.uniform(0.02, 0.06), rng.uniform(10, 60), rng.uniform(2, 8)
            mass = sb.CoilMass(coil_diameter=D, active_coils=n, wire_length=wire, material="music_wire")
            value = coil_mass(k, D, n, wire, 81.0e9, 7800.0)
        else:
            mass = value = rng.uniform(0.1, 1.5)
        kind = ("extension", "compression", "zero_free_length")[index]
        if kind == "extension":
            springs.append(
                sb.ExtensionSpring(
                    sb.Anchor(body_a, pa),
                    sb.Anchor(body_b, pb),
                    stiffness=k,
                    free_length=l0,
                    keep_tension=False,
                    mass=mass,
                )
            )
            reference.append(RefSpring(body_a, tuple(pa), body_b, tuple(pb), k, l0, mass=value))
        elif kind == "compression":
            springs.append(
                sb.CompressionSpring(
                    sb.Anchor(body_a, pa),
                    sb.Anchor(body_b, pb),
                    stiffness=k,
                    free_length=l0,
                    preload=5.0,
                    stays_compressed=False,
                    mass=mass,
                )
            )
            reference.append(RefSpring(body_a, tuple(pa), body_b, tuple(pb), k, l0, 5.0, law="compression", mass=value))
        else:
            springs.append(
                sb.ZeroFreeLengthSpring(sb.Anchor(body_a, pa), sb.Anchor(body_b, pb), stiffness=k, mass=mass)
            )
            reference.append(RefSpring(body_a, tuple(pa), body_b, tuple(pb), k, zero_free_length=True, mass=value))
    problem = sb.DesignProblem(ur5, workspace, springs)
    evaluation = problem.evaluate(np.zeros(0))
    potential = ReferencePotential(ur5.model, reference)
    for i, q in enumerate(workspace.configurations):
        expected = potential.torque(q)
        np.testing.assert_allclose(evaluation.tau[i], expected, rtol=0, atol=1e-6 * max(np.max(np.abs(expected)), 1.0))
        assert evaluation.potential[i] == pytest.approx(potential(q), rel=1e-10, abs=1e-10)
    masses = [record["mass"] for record in sb.DesignResult(problem, np.zeros(0)).springs]
    np.testing.assert_allclose(masses, [spring.mass for spring in reference], rtol=1e-12)


def test_coupled_mass_follows_k_inside_the_optimisation():
    """The design derivative sees m_s(k): d tau/dk from the CasADi function equals the
    finite difference of tau in k, which includes the √k mass term."""
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 9, ranges={"pivot": (2 * np.pi / 3, np.pi)})
    coil = sb.CoilMass(coil_diameter=0.04, active_coils=80, wire_length=10.38, shear_modulus=81e9, density=7800)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, 0.16)), sb.Anchor("link1", (0, 0, 0.3)), stiffness=sb.Free(1, 2000), mass=coil
    )
    problem = sb.DesignProblem(mechanism, workspace, [spring])
    import casadi as ca

    x = ca.SX.sym("x", 1)
    tau = problem.model.sample(x, problem.data[:, 3])[0]
    derivative = float(ca.Function("d", [x], [ca.jacobian(tau, x)])(324.0))
    step = 1e-3
    finite = (problem.evaluate([324.0 + step]).tau[3, 0] - problem.evaluate([324.0 - step]).tau[3, 0]) / (2 * step)
    assert derivative == pytest.approx(finite, rel=1e-6)
    # and it differs from the massless slope by the mass term -(1/2) dm/dk g r sin(phi)
    phi = workspace.joint_values[3, 0]
    massless = 0.16 * 0.3 * np.sin(phi)  # d/dk of k Y_B r sin(phi)
    dm_dk = coil_mass(324.0, 0.04, 80, 10.38, 81e9, 7800) / (2 * 324.0)
    assert derivative == pytest.approx(massless - 0.5 * dm_dk * 9.81 * 0.3 * np.sin(phi), rel=1e-9)
