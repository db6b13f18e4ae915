"""Exact balance with zero-free-length springs: the planar stiffness-matrix analysis.

The double pendulum is urdf/two_link_planar.urdf (documented there): link1 0.5 m, 2.0 kg
with its centre of mass at 0.25 m; link2 0.4 m, 1.0 kg at 0.2 m plus a 0.5 kg tool at its
tip; g = 9.81. Its weight moments are ``m1 c1 + (m2 + m_tool) l1 = 1.25 kg·m`` on the
shoulder's direction and ``m2 c2 + m_tool l2 = 0.4 kg·m`` on the forearm's.

Physics asserted here, not values read from the code:

- with springs ground→distal and proximal→distal the synthesis returns anchors whose
  residual torque, evaluated with Pinocchio through DesignProblem/DesignResult over the
  full torus of joint angles, is below 1e-9 of the unbalanced peak;
- with springs ground→proximal and proximal→distal nothing can cancel the distal link's
  weight moment (the ground–distal block ``g · 0.4 kg·m = 3.924 N·m``): the tool says so,
  and the general optimiser's best residual stays well above zero;
- the stiffness blocks predict the Pinocchio total potential at every pose
  (``V = const + Σ_{i<j} Re(conj(w_i) K_ij w_j)``);
- the count: n bodies → n(n−1) scalar conditions, ⌈n(n−1)/4⌉ springs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance import exact

URDF = Path(__file__).resolve().parents[2] / "urdf"
G = 9.81
DISTAL_MOMENT = 1.0 * 0.2 + 0.5 * 0.4  # [kg·m]
PROXIMAL_MOMENT = 2.0 * 0.25 + 1.5 * 0.5  # [kg·m]


@pytest.fixture(scope="module")
def pendulum():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    workspace = sb.Workspace.sobol(
        mechanism, 512, ranges={"shoulder": [-180, 180], "elbow": [-180, 180]}, degrees=True, seed=1
    )
    return mechanism, workspace


def test_chain_reads_the_urdf(pendulum):
    mechanism, _ = pendulum
    chain = exact.PlanarChain.from_mechanism(mechanism)
    assert chain.bodies == ("universe", "link1", "link2")
    gravity = chain.gravity_blocks()
    assert abs(gravity[1]) == pytest.approx(G * PROXIMAL_MOMENT, rel=1e-12)
    assert abs(gravity[2]) == pytest.approx(G * DISTAL_MOMENT, rel=1e-12)


def test_count_check():
    assert exact.count_check(3, 2).conditions == 6 and exact.count_check(3, 2).enough
    assert exact.count_check(3, 2).minimum_springs == 2
    assert not exact.count_check(3, 1).enough
    assert exact.count_check(4, 3).conditions == 12 and exact.count_check(4, 3).minimum_springs == 3
    assert exact.count_check(5, 4).minimum_springs == 5  # ⌈20/4⌉


def test_double_pendulum_synthesis_balances_exactly(pendulum):
    mechanism, workspace = pendulum
    synthesis = exact.synthesize(mechanism, [("universe", "link2", 300.0), ("link1", "link2", 200.0)])
    assert synthesis.reachable and synthesis.definitive
    springs = synthesis.require()
    assert [s.parameters["stiffness"] for s in springs] == [300.0, 200.0]
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, springs), np.zeros(0))
    unbalanced = np.max(np.abs(workspace.kinematics().gravity_torque))
    assert unbalanced == pytest.approx(G * (PROXIMAL_MOMENT + DISTAL_MOMENT), rel=1e-3)  # both links level
    assert np.max(np.abs(result.residual_torque())) < 1e-9 * unbalanced
    balance = result.exact_balance()
    assert balance["exact"] and balance["potential_spread"] < 1e-9 * unbalanced
    table = result.table()
    assert "Exactly balanced" in table and f"{balance['potential']:.6g} J" in table
    # the analysis of the design it returned agrees: every off-diagonal block vanishes
    blocks = exact.residual_blocks(mechanism, springs)
    assert blocks.exact and blocks.largest < 1e-9 * G * DISTAL_MOMENT
    # and so does the analysis of the DesignResult
    assert exact.residual_blocks(None, result).largest == pytest.approx(blocks.largest, abs=1e-12)


def test_consecutive_springs_cannot_balance_two_links(pendulum):
    mechanism, workspace = pendulum
    synthesis = exact.synthesize(mechanism, [("universe", "link1", 300.0), ("link1", "link2", 200.0)])
    assert not synthesis.reachable and synthesis.definitive
    assert "link2" in synthesis.reason and "3.924" in synthesis.reason
    with pytest.raises(exact.ExactBalanceUnreachable):
        synthesis.require()
    # the general optimiser, anchors free in a generous box and stiffness free, cannot get near zero
    box = sb.Free(lower=[-0.6, 0, -0.6], upper=[0.6, 0, 0.6])
    springs = [
        sb.ZeroFreeLengthSpring(sb.Anchor(a, box), sb.Anchor(b, box), stiffness=sb.Free(0, 2000))
        for a, b in (("universe", "link1"), ("link1", "link2"))
    ]
    best = sb.solve(sb.DesignProblem(mechanism, workspace, springs), starts=8)
    unbalanced = np.max(np.abs(workspace.kinematics().gravity_torque))
    relative = np.max(np.abs(best.residual_torque())) / unbalanced
    print(f"[exact] consecutive springs: optimiser's best peak residual {100 * relative:.3g} % of the unbalanced peak")
    assert relative > 0.05
    assert not best.exact_balance()["exact"]
    assert "Exactly balanced" not in best.table()
    # the same optimiser with the reachable topology does reach exact balance
    springs = [
        sb.ZeroFreeLengthSpring(sb.Anchor(a, box), sb.Anchor(b, box), stiffness=sb.Free(0, 2000))
        for a, b in (("universe", "link2"), ("link1", "link2"))
    ]
    assert sb.solve(sb.DesignProblem(mechanism, workspace, springs), starts=8).exact_balance()["exact"]


def test_blocks_predict_the_pinocchio_potential(pendulum):
    mechanism, workspace = pendulum
    springs = [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", (0.05, 0.02, 0.3)), sb.Anchor("link2", (0.1, 0.0, -0.05)), stiffness=150.0
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("link1", (0.2, 0.0, 0.1)), sb.Anchor("link2", (-0.1, 0.03, 0.05)), stiffness=80.0
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", (-0.1, 0.0, 0.1)), sb.Anchor("link1", (0.3, 0.0, 0.0)), stiffness=60.0
        ),
    ]
    potential = sb.DesignProblem(mechanism, workspace, springs).evaluate(np.zeros(0)).potential
    blocks = exact.residual_blocks(mechanism, springs).blocks
    q = workspace.joint_values
    w = {"universe": np.ones(len(q)), "link1": np.exp(1j * q[:, 0]), "link2": np.exp(1j * (q[:, 0] + q[:, 1]))}
    predicted = sum(np.real(np.conj(w[a]) * value * w[b]) for (a, b), value in blocks.items())
    offset = potential - predicted
    assert np.ptp(offset) < 1e-9 * np.ptp(potential)
    matrices = exact.residual_blocks(mechanism, springs).matrices()
    for pair, value in blocks.items():
        e = np.array([np.cos(0.3), np.sin(0.3)]), np.array([np.cos(-1.1), np.sin(-1.1)])
        assert e[0] @ matrices[pair] @ e[1] == pytest.approx(np.real(np.exp(-0.3j) * value * np.exp(-1.1j)), abs=1e-12)


def test_three_link_chain_synthesis():
    links = "".join(
        f"""
  <link name="l{i}"><inertial><origin xyz="{c} 0 0"/><mass value="{m}"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j{i}" type="continuous"><parent link="{"base" if i == 1 else f"l{i - 1}"}"/><child link="l{i}"/>
    <origin xyz="{0 if i == 1 else length} 0 0"/><axis xyz="0 -1 0"/></joint>"""
        for i, (m, c, length) in enumerate([(2.0, 0.2, 0.0), (1.5, 0.15, 0.4), (1.0, 0.1, 0.3)], start=1)
    )
    mechanism = sb.Mechanism.from_urdf_string(f'<robot name="three"><link name="base"/>{links}</robot>')
    topology = [("universe", "l3", 400.0), ("l1", "l3", 300.0), ("universe", "l2", 300.0), ("l2", "l3", 200.0)]
    synthesis = exact.synthesize(mechanism, topology)
    assert synthesis.count.conditions == 12 and synthesis.count.enough
    assert synthesis.reachable
    workspace = sb.Workspace.sobol(mechanism, 256, seed=2)
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, synthesis.springs), np.zeros(0))
    assert result.exact_balance()["relative_residual"] < 1e-9


def test_analysis_rejects_what_it_cannot_model():
    with pytest.raises(sb.InputError, match="mimic"):
        exact.PlanarChain.from_mechanism(sb.Mechanism.from_urdf(URDF / "parallelogram_arm.urdf", mimic=True))
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    with pytest.raises(sb.InputError, match="zero-free-length"):
        exact.residual_blocks(
            mechanism,
            [
                sb.ExtensionSpring(
                    sb.Anchor("universe", (0, 0, 0.1)),
                    sb.Anchor("link1", (0.2, 0, 0)),
                    stiffness=10.0,
                    free_length=0.05,
                )
            ],
        )
    with pytest.raises(sb.InputError, match="unknown body"):
        exact.synthesize(mechanism, [("universe", "nowhere", 10.0)])
    text = (URDF / "two_link_planar.urdf").read_text()
    head, tail = text.split('<joint name="elbow"', 1)
    spatial = sb.Mechanism.from_urdf_string(
        head + '<joint name="elbow"' + tail.replace('<axis xyz="0 -1 0"/>', '<axis xyz="1 0 0"/>', 1)
    )
    with pytest.raises(sb.InputError, match="not planar"):
        exact.synthesize(spatial, [("universe", "link2", 10.0)])


def test_synthesis_with_opposite_joint_axes():
    # the same double pendulum with the elbow axis flipped: absolute angles are shoulder - elbow,
    # which changes the coordinates but not the physics, so exact balance is still reachable
    text = (URDF / "two_link_planar.urdf").read_text()
    head, tail = text.split('<joint name="elbow"', 1)
    flipped = head + '<joint name="elbow"' + tail.replace('<axis xyz="0 -1 0"/>', '<axis xyz="0 1 0"/>', 1)
    mechanism = sb.Mechanism.from_urdf_string(flipped)
    synthesis = exact.synthesize(mechanism, [("universe", "link2", 250.0), ("link1", "link2", 250.0)])
    workspace = sb.Workspace.sobol(
        mechanism, 256, ranges={"shoulder": [-180, 180], "elbow": [-180, 180]}, degrees=True, seed=4
    )
    result = sb.DesignResult(sb.DesignProblem(mechanism, workspace, synthesis.require()), np.zeros(0))
    assert result.exact_balance()["relative_residual"] < 1e-9


def test_exact_balance_judges_only_joints_with_weight():
    """A single-link balance on the shoulder of the two-link arm with the elbow held straight: with the
    elbow's weight 0 the shoulder is exactly balanced (k a b = m g c of the rigid pair), with weight 1 not."""
    import springbalance as sb

    mechanism = sb.Mechanism.from_urdf("urdf/two_link_planar.urdf", gravity=9.81)
    workspace = sb.Workspace.grid(mechanism, {"shoulder": 91, "elbow": 1}, ranges={"elbow": [0, 0]})
    moment = (2.0 * 0.25 + 1.0 * 0.7 + 0.5 * 0.9) * 9.81  # Σ m c g of link1, link2, tool [N·m]
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", [0, 0, 0.1]), sb.Anchor("link1", [0.3, 0, 0]), stiffness=moment / (0.1 * 0.3)
    )
    shoulder_only = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring], weights={"elbow": 0}), np.zeros(0))
    both = sb.DesignResult(sb.DesignProblem(mechanism, workspace, [spring]), np.zeros(0))
    assert shoulder_only.exact_balance()["exact"]
    assert "Exactly balanced on the joints with weight > 0" in shoulder_only.table()
    assert not both.exact_balance()["exact"]  # the elbow still carries link2's weight
