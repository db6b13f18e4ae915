"""A coil's length rule and its body stress searched to their least margins inside the workspace's box
(springbalance.design.verification_refine): the least length of a spring from the ground to a link lies at a
joint limit, which Sobol points never reach."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design.verification import check_design
from springbalance.design.verification_refine import (
    APART,
    STARTS_PER_RULE,
    margins,
    refined_poses,
    search_box,
    search_starts,
    spring_joints,
)

URDF = Path(__file__).resolve().parents[2] / "urdf"
A, R = 0.3, 0.2  # [m] the ground anchor's height above the shoulder, the link-1 anchor's distance along it
RANGES = {"shoulder": [-1.0, 1.2], "elbow": [-2.0, 2.0]}
COIL = {"wire_diameter": 0.002, "mean_diameter": 0.02, "active_coils": 20.0, "initial_tension": 5.0}


@pytest.fixture(scope="module")
def problem():
    arm = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    coil = sb.HelicalExtensionSpring(sb.Anchor("universe", [0, 0, A]), sb.Anchor("link1", [R, 0, 0]), "c", **COIL)
    return sb.DesignProblem(arm, sb.Workspace.sobol(arm, n=16, ranges=RANGES, seed=0), [coil])


def test_the_search_reaches_the_joint_limit_where_the_coil_is_shortest(problem):
    """Link 1 turns about −y, so its anchor is at R (cos θ, 0, sin θ) and ``L² = A² + R² − 2 A R sin θ``: over
    θ ∈ [−1, 1.2] the least length is at θ = 1.2, and the margin there is ``L − l0`` with the closed coil's
    ``l0 = d (n + 1) + 2 (D − d)``; the elbow does not move the coil."""
    x = np.asarray(problem.variables.start, dtype=float)
    box = search_box(problem.workspace)
    assert box is not None
    block = next(b for b in problem.model.constraint_blocks if b.name == "tension")
    found = refined_poses(problem, x, [(block.offset, np.array([0.0, 0.5]))], box)
    assert found[0, 0] == pytest.approx(1.2, abs=1e-12)
    d, D, n = COIL["wire_diameter"], COIL["mean_diameter"], COIL["active_coils"]
    least = np.sqrt(A**2 + R**2 - 2 * A * R * np.sin(1.2)) - (d * (n + 1) + 2 * (D - d))
    assert margins(problem, x, found, [block])[0, 0] == pytest.approx(least, abs=1e-9)
    # the searches start apart along the shoulder, the joint the coil depends on (the elbow does not count)
    every = search_starts(problem, x, problem.workspace.joint_values, box)
    # the length rule and the body stress (the coil's largest force) are searched, each from its own starts
    stress = next(b for b in problem.model.constraint_blocks if b.name == "body_stress")
    assert {offset for offset, _ in every} == {block.offset, stress.offset}
    starts = [(offset, pose) for offset, pose in every if offset == block.offset]
    assert 1 <= len(starts) <= STARTS_PER_RULE
    shoulders = sorted(pose[0] for _, pose in starts)
    assert np.all(np.diff(shoulders) >= APART * 2.2)


def test_the_verification_judges_the_searched_poses(problem):
    """The verification's worst margin of the length rule is the one at the joint limit, below every Sobol
    pose's."""
    x = np.asarray(problem.variables.start, dtype=float)
    rule = next(r for r in check_design(problem, x).record.rules if r.rule == "tension")
    assert rule.pose["shoulder"] == pytest.approx(1.2, abs=1e-12)
    assert rule.margin < rule.sampled


def test_the_body_stress_is_searched_to_the_limit_where_the_coil_is_longest(problem):
    """The same coil's largest force is at its longest length, θ = −1 (``L² = A² + R² − 2 A R sin θ``): there
    ``F = F_i + k (L − l0)`` with ``k = G d⁴/(8 D³ n)``, and the body stress margin is ``1 − τ/(0.45 S_ut)`` with
    ``τ = K_B 8 F D/(π d³)``, ``K_B = (4C + 2)/(4C − 3)``, music wire's ``G = 81.0 GPa`` at 1.6–3.2 mm and
    ``S_ut = 2211 MPa·mm^0.145 / d^0.145``
    (Shigley Tables 10-4, 10-5 and 10-6)."""
    x = np.asarray(problem.variables.start, dtype=float)
    box = search_box(problem.workspace)
    assert box is not None
    block = next(b for b in problem.model.constraint_blocks if b.name == "body_stress")
    found = refined_poses(problem, x, [(block.offset, np.array([0.3, -1.0]))], box)
    assert found[0, 0] == pytest.approx(-1.0, abs=1e-12)
    d, D, n, initial = (COIL[key] for key in ("wire_diameter", "mean_diameter", "active_coils", "initial_tension"))
    length = np.sqrt(A**2 + R**2 - 2 * A * R * np.sin(-1.0))
    force = initial + 81.0e9 * d**4 / (8 * D**3 * n) * (length - (d * (n + 1) + 2 * (D - d)))
    index = D / d
    stress = (4 * index + 2) / (4 * index - 3) * 8 * force * D / (np.pi * d**3)
    strength = 2211e6 / (d * 1e3) ** 0.145
    assert margins(problem, x, found, [block])[0, 0] == pytest.approx(1 - stress / (0.45 * strength), abs=1e-9)


def test_a_compression_coil_stays_compressed_is_searched_to_where_it_is_longest():
    """A helical compression coil between the same anchors: its ``L ≤ l0`` binds at its longest length, θ = −1
    (``L² = A² + R² − 2 A R sin θ``), where the margin is ``l0 − L`` (the optimisation's 1 mm reserve added
    back); its solid length, ``L − d (n + 2)``, binds at its shortest, θ = 1.2, where its force (and so its
    body stress) is largest."""
    arm = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    d, n, free = 0.002, 10.0, 0.5  # [m], [1], [m]
    coil = sb.HelicalCompressionSpring(
        sb.Anchor("universe", [0, 0, A]),
        sb.Anchor("link1", [R, 0, 0]),
        "p",
        wire_diameter=d,
        mean_diameter=0.02,
        active_coils=n,
        free_length=free,
        guided=True,
    )
    problem = sb.DesignProblem(arm, sb.Workspace.sobol(arm, n=16, ranges=RANGES, seed=0), [coil])
    x = np.asarray(problem.variables.start, dtype=float)
    box = search_box(problem.workspace)
    assert box is not None
    blocks = {b.name: b for b in problem.model.constraint_blocks}
    every = search_starts(problem, x, problem.workspace.joint_values, box)
    assert {offset for offset, _ in every} == {blocks["stays_compressed"].offset, blocks["body_stress"].offset}
    longest = refined_poses(problem, x, [(blocks["stays_compressed"].offset, np.array([0.3, 0.5]))], box)
    assert longest[0, 0] == pytest.approx(-1.0, abs=1e-12)
    length = np.sqrt(A**2 + R**2 - 2 * A * R * np.sin(-1.0))
    assert margins(problem, x, longest, [blocks["stays_compressed"]])[0, 0] == pytest.approx(free - length, abs=1e-9)
    shortest = refined_poses(problem, x, [(blocks["body_stress"].offset, np.array([0.3, 0.5]))], box)
    assert shortest[0, 0] == pytest.approx(1.2, abs=1e-12)
    length = np.sqrt(A**2 + R**2 - 2 * A * R * np.sin(1.2))
    assert margins(problem, x, shortest, [blocks["solid"]])[0, 0] == pytest.approx(length - d * (n + 2), abs=1e-9)


def test_a_search_moves_only_the_joints_between_its_springs_bodies():
    """On the two-link arm a coil from the ground to link 1 depends on the shoulder only, one from link 1 to
    link 2 on the elbow only (the shoulder moves both of its bodies alike), one from the ground to link 2 on
    both: the compass search tries only those joints, and a search with nothing to move stays where it starts."""
    arm = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    pairs = {"g1": ("universe", "link1"), "12": ("link1", "link2"), "g2": ("universe", "link2")}
    coils = [
        sb.HelicalExtensionSpring(sb.Anchor(a, [0.05, 0, 0.1]), sb.Anchor(b, [0.2, 0, 0.02]), name, **COIL)
        for name, (a, b) in pairs.items()
    ]
    problem = sb.DesignProblem(arm, sb.Workspace.sobol(arm, n=16, ranges=RANGES, seed=0), coils)
    tension = {b.spring: b for b in problem.model.constraint_blocks if b.name == "tension"}
    expected = {"g1": [True, False], "12": [False, True], "g2": [True, True]}
    for name, moved in expected.items():
        assert spring_joints(problem, tension[name]).tolist() == moved, name
    x = np.asarray(problem.variables.start, dtype=float)
    box = search_box(problem.workspace)
    assert box is not None
    start = np.array([0.3, 0.5])
    found = refined_poses(problem, x, [(tension["g1"].offset, start), (tension["12"].offset, start)], box)
    assert found[0, 1] == start[1] and found[1, 0] == start[0]  # the joint a spring does not depend on stays put
    fixed = (np.array([0.3, -2.0]), np.array([0.3, 2.0]))  # the elbow alone may move: g1 has nothing to search
    assert np.array_equal(refined_poses(problem, x, [(tension["g1"].offset, start)], fixed)[0], start)
