"""The two-link arm with one free helical extension spring that states a fatigue duty (10⁶ cycles): the problem
the fatigue-row tests (design/test_fatigue_bounds.py, design/test_floors.py) solve."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import springbalance as sb

URDF = Path(__file__).resolve().parents[1] / "urdf"
RANGES = {"shoulder": [-np.pi / 2, np.pi / 2], "elbow": [-2.0, 2.0]}


def duty_coil_problem(samples: int) -> sb.DesignProblem:
    """urdf/two_link_planar.urdf, a music-wire coil ``forearm`` from the ground to link2 (outer diameter ≤ 40 mm,
    ``duty: {cycles: 1e6}``) and ``samples`` Sobol poses (seed 0) of :data:`RANGES`."""
    arm = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    coil = sb.HelicalExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.3, 0, -0.1], [0.3, 0, 0.6])),
        sb.Anchor("link2", sb.Free([0.02, 0, 0], [0.4, 0, 0])),
        "forearm",
        max_outer_diameter=0.04,
        duty={"cycles": 1e6},
    )
    return sb.DesignProblem(arm, sb.Workspace.sobol(arm, n=samples, ranges=RANGES, seed=0), [coil])
