"""Robust design over the springs' tolerance box (docs/model.md §3.10): its worst build and its solve time
against the nominal design's, on the two-link arm with two ideal extension springs (anchors in boxes; k,
l0 and F0 free), 24 random poses, ±10 % rate, ±3 N initial tension, ±4 mm free length.

Designs: nominal (robust off), robust over the exact 16 corners, the same with 6 mm preload screws per
corner, and the cheaper corner sets (strong_weak, uniform). Each design's worst build is the RMS of the
worst of the 16 exact corners of its springs as built (tests/design/test_robust_tolerance.py shows they
reach the worst of all 64 builds), without and with the best screw settings within the travel.

    python benchmarks/bench_robust.py [starts]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import springbalance as sb

URDF = Path(__file__).resolve().parents[1] / "urdf" / "two_link_planar.urdf"
BOX = {"grade": None, "rate": 0.1, "initial_tension": 3.0, "free_length": 0.004}
TRAVEL = 0.006  # [m]


def springs() -> list:
    box = sb.Free
    return [
        sb.ExtensionSpring(
            sb.Anchor("universe", box((-0.05, 0, 0.05), (0.05, 0, 0.3))), sb.Anchor("link1", box((0.05, 0, 0), (0.5, 0, 0))),
            "shoulder", stiffness=box(100, 3000), free_length=box(0.02, 0.2), initial_tension=box(5, 50), keep_tension=False,
        ),
        sb.ExtensionSpring(
            sb.Anchor("universe", box((-0.3, 0, -0.1), (0.3, 0, 0.6))), sb.Anchor("link2", box((0.02, 0, 0), (0.4, 0, 0))),
            "forearm", stiffness=box(50, 2000), free_length=box(0.02, 0.2), initial_tension=box(5, 50), keep_tension=False,
        ),
    ]  # fmt: skip


def worst_build(result: sb.DesignResult, travel: float | None) -> float:
    """The worst RMS [N·m] over the box of ``result``'s springs as built (each corner re-balanced within
    ``travel`` when given): the optimum of the exact robust problem with every spring variable fixed."""
    problem = result.problem
    nominal, x = problem.scenario_problem(0), problem.model.scenario_vector(result.x, 0)
    fixed = nominal.scenario_springs(x, 0)
    spec = sb.ToleranceSpec(**BOX, robust=True, adjuster_travel=travel)
    check = sb.DesignProblem(problem.mechanism, problem.base_workspace, fixed, tolerance=spec)
    if travel is None:
        return check.objective_value(check.evaluate(np.zeros(0)))
    settled = sb.solve(check, starts=1, progress=False, verify="off", workers=1)
    return check.objective_value(settled.evaluation)


def main(starts: int = 4) -> None:
    mechanism = sb.Mechanism.from_urdf(URDF)
    workspace = sb.Workspace.from_array(mechanism, np.random.default_rng(3).uniform(-1.2, 1.2, size=(24, 2)))
    cases = [
        ("nominal", sb.ToleranceSpec(**BOX)),
        ("robust exact", sb.ToleranceSpec(**BOX, robust=True)),
        ("robust exact + screws", sb.ToleranceSpec(**BOX, robust=True, adjuster_travel=TRAVEL)),
        ("robust strong_weak", sb.ToleranceSpec(**BOX, robust=True, corners="strong_weak")),
        ("robust uniform", sb.ToleranceSpec(**BOX, robust=True, corners="uniform")),
    ]
    print(
        f"{'design':<24s}{'cases':>6s}{'time [s]':>10s}{'ratio':>7s}{'nominal rms':>13s}{'worst':>8s}{'worst+screws':>14s}"
    )
    reference = None
    sb.solve(
        sb.DesignProblem(mechanism, workspace, springs()), starts=1, progress=False, verify="off", workers=1
    )  # warm-up
    for label, spec in cases:
        problem = sb.DesignProblem(mechanism, workspace, springs(), tolerance=spec)
        start = time.perf_counter()
        result = sb.solve(problem, starts=starts, progress=False, verify="off", workers=1)
        seconds = time.perf_counter() - start
        reference = reference or seconds
        nominal, x = problem.scenario_problem(0) if problem.corners else problem, result.x
        x = problem.model.scenario_vector(x, 0) if problem.corners else x
        rms = float(np.sqrt(np.mean(nominal.evaluate(x).tau ** 2)))
        print(
            f"{label:<24s}{max(len(problem.scenarios), 1):>6d}{seconds:>10.2f}{seconds / reference:>7.1f}{rms:>13.4f}"
            f"{worst_build(result, None):>8.4f}{worst_build(result, TRAVEL):>14.4f}"
        )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 4)
