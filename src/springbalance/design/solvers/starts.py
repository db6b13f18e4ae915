"""Start points of the multi-start: the given ones, then scrambled Sobol points in the unit box."""

from __future__ import annotations

import numpy as np

from springbalance.design.solvers.records import Problem
from springbalance.model.sobol import sobol_engine


def start_points(
    problem: Problem, starts: int, seed: int, initial: np.ndarray | None = None, fixed: np.ndarray | None = None
) -> np.ndarray:
    """Scaled start points: ``initial`` (physical units; one point, or one per row of a 2-D array)
    or the problem's initial guess, then scrambled Sobol points in [0, 1]^n up to ``starts`` points
    in all; the variables of the boolean mask ``fixed`` keep their value of the first point in every
    Sobol point (and each given point its own)."""
    n = problem.variables.size
    guess = problem.variables.start if initial is None else initial
    given = np.clip(problem.unscale(np.atleast_2d(np.asarray(guess, dtype=float))), 0.0, 1.0)
    count = max(int(starts) - given.shape[0], 0)
    if count == 0 or n == 0:
        return given
    sobol = sobol_engine(n, np.random.default_rng(seed))
    others = sobol.random(1 << int(np.ceil(np.log2(count)))) if count > 1 else sobol.random(1)
    points = np.vstack([given, others[:count]])
    if fixed is not None:
        points[given.shape[0] :, fixed] = given[0, fixed]
    return points
