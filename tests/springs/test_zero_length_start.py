"""A zero-free-length spring whose ends start at the same point (the centres of two boxes about one
joint axis, as a study's candidate boxes often are) must not poison the solver: ``√(d·d)`` has no
derivative at 0, so the law's potential is written in ``L²`` (``k L²/2``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf" / "two_link_planar.urdf"


def test_potential_objective_from_coincident_ends_solves():
    mechanism = sb.Mechanism.from_urdf(URDF)
    workspace = sb.Workspace.sobol(mechanism, n=32, seed=0)
    box = lambda: sb.Free([-0.3] * 3, [0.3] * 3)  # noqa: E731  centred on the shoulder axis: ends start together
    springs = [
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", box()), sb.Anchor("link1", box()), "s1", stiffness=sb.Free(0, 5000)
        ),
        sb.ZeroFreeLengthSpring(
            sb.Anchor("universe", box()), sb.Anchor("link2", box()), "s2", stiffness=sb.Free(0, 5000)
        ),
    ]
    problem = sb.DesignProblem(mechanism, workspace, springs, objective="pe_variance")
    start = problem.evaluate(np.asarray(problem.variables.start, dtype=float))
    assert np.min(start.lengths[:, 0]) == 0.0  # the first spring's ends do coincide at the start
    result = sb.solve(problem, starts=2, seed=3, progress=False)
    after = result.metrics()["objectives"]["pe_variance"]
    assert np.isfinite(after["after"]) and after["after"] < after["before"]
