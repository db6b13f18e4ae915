"""The floor the arm stands on (``mechanism: {floor: h}``): a collision object of the ground that the springs keep
clear of, as they keep clear of the links.

The two-link arm of urdf/two_link_planar_collision.urdf (shoulder at the world origin, both joints about −y) with
link1 held above the horizontal, a floor 0.15 m below the shoulder, and a link1 → link2 spring whose link1 anchor
may hang 0.4 m below the link: from an anchor at the bottom of that box the spring passes through the floor
(link1 at 0.3 rad: the anchor at z = 0.1 sin 0.3 − 0.4 cos 0.3 = −0.35 m), and the fit to the arm must lift it
``margin`` clear of the floor at 10× the poses it was fitted on.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.cli import main
from springbalance.design.clearance_fit import fit_to_arm
from springbalance.design.solvers import Solution
from springbalance.io.config import load_config
from springbalance.model.collision import CollisionScene
from springbalance.model.floor import FLOOR

URDF = Path(__file__).resolve().parents[2] / "urdf" / "two_link_planar_collision.urdf"
FLOOR_HEIGHT = -0.15  # [m], world z
MARGIN = 0.005  # [m]
CHECK = 128  # poses the fit checks
RANGES = {"shoulder": [0.3, 1.2], "elbow": [-1.0, 0.5]}


def _problem(floor: float | None) -> sb.DesignProblem:
    arm = sb.Mechanism.from_urdf(URDF, floor=floor)
    workspace = sb.Workspace.sobol(arm, n=64, ranges=RANGES, seed=0)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("link1", sb.Free([0.05, -0.05, -0.4], [0.45, 0.05, 0.05], init=[0.1, 0.0, -0.4])),
        sb.Anchor("link2", sb.Free([0.02, -0.05, -0.05], [0.4, 0.05, 0.05], init=[0.2, 0.0, 0.0])),
        stiffness=sb.Free(0, 5000, init=100.0),
        name="hanging",
    )
    return sb.DesignProblem(arm, workspace, [spring], clearance=sb.Clearance(margin=MARGIN, check_samples=CHECK))


def test_the_floor_is_an_object_of_the_ground_named_floor_and_ground_springs_are_exempt():
    arm = sb.Mechanism.from_urdf(URDF, floor=FLOOR_HEIGHT)
    scene = CollisionScene(arm, convex=True)
    floor = scene.links.index(FLOOR)
    assert scene.bodies[floor] == "universe"
    assert floor not in scene.indices_except(["universe", "link1"])  # a ground → link1 spring
    assert floor not in scene.indices_except(["base", "link2"])  # a spring from the arm's base (welded to the ground)
    assert floor in scene.indices_except(["link1", "link2"])
    scene.place(np.zeros(arm.nv))
    for z, expected in ((0.1, 0.1 - FLOOR_HEIGHT - 0.01), (-0.2, -0.2 - FLOOR_HEIGHT - 0.01)):
        contact = scene.capsule_distance(np.array([0.3, 0.2, z]), np.array([0.3, 0.4, z]), 0.01, floor)
        assert contact.distance == pytest.approx(expected, abs=1e-5)  # above: the gap; below: the depth (GJK, EPA)
        assert contact.normal == pytest.approx([0.0, 0.0, 1.0], abs=1e-9)
    assert CollisionScene(sb.Mechanism.from_urdf(URDF)).links.count(FLOOR) == 0  # no floor unless asked for


def test_a_spring_through_the_floor_is_fitted_clear_of_it():
    problem = _problem(FLOOR_HEIGHT)
    start = np.asarray(problem.variables.start, dtype=float)
    before = sb.DesignResult(problem, start).clearance(samples=10 * CHECK)
    assert before.row("hanging").link == FLOOR and before.row("hanging").distance < -0.1  # through the floor
    solution, fit, _ = fit_to_arm(
        problem, Solution(start, [], "auto", 0, "given"), method="auto", max_iterations=100, tolerance=1e-8
    )
    assert fit.converged and fit.rows > 0
    after = sb.DesignResult(problem, solution.x, fit=fit).clearance(samples=10 * CHECK)  # poses the fit never saw
    assert after.row("hanging").distance >= MARGIN, str(after)


def test_without_a_floor_the_same_start_is_clear_as_it_is():
    problem = _problem(None)
    report = sb.DesignResult(problem, np.asarray(problem.variables.start, dtype=float)).clearance(samples=10 * CHECK)
    assert report.row("hanging").distance > 0 and report.row("hanging").link != FLOOR


def test_the_floor_is_saved_with_the_design_and_checked_again_from_the_file(tmp_path):
    problem = _problem(FLOOR_HEIGHT)
    result = sb.DesignResult(problem, np.asarray(problem.variables.start, dtype=float))
    path = tmp_path / "design.json"
    result.save(path)
    loaded = sb.DesignResult.load(path)
    assert loaded.problem.mechanism.floor == FLOOR_HEIGHT
    report = loaded.clearance(samples=CHECK)
    assert report.row("hanging").link == FLOOR and "and to the floor" in str(report).splitlines()[0]
    assert main(["clearance", str(path), "--samples", str(CHECK)]) == 3  # the spring through the floor fails


CONFIG = """
mechanism: {{urdf: {urdf}, floor: {floor}}}
workspace: {{kind: sobol, n: 32, ranges: {{shoulder: [0.3, 1.2], elbow: [-1.0, 0.5]}}}}
springs:
  - {{name: hanging, type: zero_free_length, a: {{body: link1, point: [0.1, 0, -0.4]}},
     b: {{body: link2, point: [0.2, 0, 0]}}, stiffness: 50}}
"""


@pytest.mark.parametrize(
    "floor, culprit", [("[0, 0]", "mechanism.floor"), ("1.0e+3", "mechanism.floor"), (".nan", "floor")]
)
def test_a_bad_floor_gets_one_line_naming_it(tmp_path, capsys, floor, culprit):
    config = tmp_path / "floor.yaml"
    config.write_text(CONFIG.format(urdf=URDF, floor=floor))
    assert main(["design", str(config), "--out", str(tmp_path / "d.json")]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and culprit in error[0], error
    assert not (tmp_path / "d.json").exists()


def test_a_floor_in_a_config_reaches_the_mechanism(tmp_path):
    config = tmp_path / "floor.yaml"
    config.write_text(CONFIG.format(urdf=URDF, floor=FLOOR_HEIGHT))
    assert load_config(config).problem.mechanism.floor == FLOOR_HEIGHT
