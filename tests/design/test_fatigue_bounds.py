"""Fatigue rows of a coil with a duty (springs/fatigue_rows.py): the bounds F_lo ≤ P_i ≤ F_hi of its force at every
sample and the damage rows of (F_lo, F_hi) once, with the solver's working set of rows (design/structured_nlp.py).

The arm is urdf/two_link_planar.urdf; one free helical extension spring of music wire from the ground to link2
lives 10⁶ cycles at n_f ≥ 1.2 (Gerber). The design starts where its largest and smallest forces are at other
samples than at the optimum, so a rule enforced only where the force was extreme at the start would miss them. At
the optimum, the force range over every sample is judged here from Shigley's formulas (Budynas & Nisbett, 10th
ed.: Eq. 10-7, 10-34 to 10-36 for the stresses, Table 10-4 for S_ut of music wire, Table 10-8 for the
fatigue strengths at 10⁶ cycles, Eq. 10-30 for S_su, Table 6-7 for Gerber's n_f), not with the package's own
fatigue functions.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import springbalance as sb
from duty_helpers import duty_coil_problem
from springbalance.design.solvers import solve_problem

#: the start: a stiff, long coil anchored far from where the optimum puts it (physical units)
START = {"forearm.a.x": 0.0, "forearm.a.z": 0.25, "forearm.b.x": 0.21, "forearm.initial_tension": 1000.0}


def gerber_factor(amplitude: float, mean: float, strength_amplitude: float, ultimate: float) -> float:
    """n_f on Gerber's load line (Shigley Table 6-7) for a fatigue point S_a = S_m = ``strength_amplitude``."""
    endurance = strength_amplitude / (1.0 - (strength_amplitude / ultimate) ** 2)  # S_e, Gerber's projection
    ratio = 2.0 * mean * endurance / (ultimate * amplitude)
    return 0.5 * (ultimate / mean) ** 2 * (amplitude / endurance) * (-1.0 + math.sqrt(1.0 + ratio * ratio))


def shigley_factors(d: float, D: float, low: float, high: float) -> dict[str, float]:
    """Gerber n_f at the body, hook A (bending) and hook B (torsion) of an extension spring of music wire, wire
    ``d`` and mean diameter ``D`` [m], whose force cycles between ``low`` and ``high`` [N], at 10⁶ cycles."""
    tensile = 2211e6 * (d * 1e3) ** -0.145  # S_ut [Pa], Table 10-4 (A = 2211 MPa·mm^m, m = 0.145)
    C = D / d
    body = (4 * C + 2) / (4 * C - 3) * 8 * D / (math.pi * d**3)  # K_B 8D/(πd³) [Pa/N]
    bend_A = (4 * C * C - C - 1) / (4 * C * (C - 1)) * 16 * D / (math.pi * d**3) + 4 / (math.pi * d**2)
    C2 = 4.0  # the hook's side-bend index 2 r_2/d
    torsion_B = (4 * C2 - 1) / (4 * C2 - 4) * 8 * D / (math.pi * d**3)
    # (stress per newton, Table 10-8 range S_r/S_ut at 10⁶ cycles, ultimate strength)
    locations = {
        "body": (body, 0.33, 0.67 * tensile),
        "hook_bending": (bend_A, 0.47, tensile),
        "hook_torsion": (torsion_B, 0.30, 0.67 * tensile),
    }
    return {
        name: gerber_factor(c * (high - low) / 2, c * (high + low) / 2, fraction * tensile / 2, ultimate)
        for name, (c, fraction, ultimate) in locations.items()
    }


@pytest.mark.slow
def test_the_optimum_meets_fatigue_over_every_sample_when_the_extreme_samples_moved():
    problem = duty_coil_problem(16)
    names = problem.variables.names
    start = np.array([START.get(name, value) for name, value in zip(names, problem.variables.start)])
    solution = solve_problem(problem, starts=1, initial=start, progress=False)
    x = dict(zip(names, solution.x))

    before = problem.evaluate(start).tensions[:, 0]
    after = problem.evaluate(solution.x).tensions[:, 0]
    # the samples of the largest and of the smallest force are not those of the start
    assert np.argmax(after) != np.argmax(before) and np.argmin(after) != np.argmin(before)
    assert np.all(after > 0)  # the coil pulls at every sample

    factors = shigley_factors(x["forearm.wire_diameter"], x["forearm.mean_diameter"], after.min(), after.max())
    for location, factor in factors.items():
        assert factor >= 1.2, (location, factor)
    # and the duty shapes the design: its weakest location is close to the required factor (the rows keep 2 %
    # of the row in reserve, a few % of n_f), not far above it
    assert min(factors.values()) < 1.3, factors


def test_a_design_saved_without_the_fatigue_ceiling_loads_with_its_largest_force(tmp_path):
    """A design file written before a coil had its ceiling variable (``<name>.fatigue_max_force``) still loads:
    the ceiling is the design's largest force over the samples, every saved value is kept."""
    problem = duty_coil_problem(8)
    names = problem.variables.names
    x = np.array([START.get(name, value) for name, value in zip(names, problem.variables.start)])
    x[names.index("forearm.fatigue_min_force")] = 123.0
    path = sb.DesignResult(problem, x).save(tmp_path / "design.json")
    record = json.loads(path.read_text(encoding="utf-8"))
    del record["variables"]["forearm.fatigue_max_force"]
    path.write_text(json.dumps(record), encoding="utf-8")

    loaded = sb.DesignResult.load(path)
    values = dict(zip(loaded.problem.variables.names, loaded.x))
    tension = problem.evaluate(x).tensions[:, 0]  # an extension spring's force [N], all positive here
    assert np.all(tension > 0)
    assert values["forearm.fatigue_max_force"] == pytest.approx(float(np.max(tension)), rel=1e-12)
    for name in names:
        if name != "forearm.fatigue_max_force":
            assert values[name] == pytest.approx(x[names.index(name)], rel=1e-12, abs=1e-15), name
