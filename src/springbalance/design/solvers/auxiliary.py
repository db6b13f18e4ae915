r"""A start's auxiliary variables at the values its design calls for (docs/model.md §3.8.2).

A coil with a duty has the bounds ``F_lo ≤ P_i ≤ F_hi`` [N] of its force at every sample as design variables
(:mod:`springbalance.springs.fatigue_rows`). Their best values for a design are its force range,
``F_lo = min_i P_i`` and ``F_hi = max_i P_i``: the bound rows then hold, and the damage rows are those of the
design's own range. A start whose forces moved since its bounds were set (its linear variables fitted, a wire
rounded to a standard size) starts from these instead of from stale bounds that break the rows.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from springbalance.design.solvers.records import Problem
from springbalance.springs.fatigue import CEILING, FLOOR, force_range


def tight_bounds(problem: Problem, z: np.ndarray) -> np.ndarray:
    """The scaled design ``z`` with each coil's fatigue bounds at the design's force range over the samples
    (clipped to their own bounds); ``z`` itself when the problem has no such variables."""
    names = problem.model.auxiliary_names
    if not names:
        return z
    index = {name: i for i, name in enumerate(problem.variables.names)}
    evaluation = problem.evaluate(problem.scale(z))
    lower, upper = problem.variables.bounds()
    tight = np.array(z, dtype=float)
    for column, spring in enumerate(problem.springs):
        keys = [index.get(f"{spring.name}.{FLOOR}"), index.get(f"{spring.name}.{CEILING}")]
        if None in keys or not np.all(np.isfinite(evaluation.tensions[:, column])):
            continue
        for i, value in zip(keys, force_range(evaluation.tensions[:, column], spring.helical_kind)):
            assert i is not None  # (checked above)
            if upper[i] > lower[i]:
                tight[i] = float(np.clip((value - lower[i]) / (upper[i] - lower[i]), 0.0, 1.0))
    return tight


def design_from_values(problem: Problem, values: Mapping[str, float]) -> np.ndarray:
    """The physical design vector of ``problem`` from ``values`` (variable name → value), each auxiliary variable
    that ``values`` lacks (a design saved before the coil's fatigue ceiling existed) at the design's force range
    (:func:`tight_bounds`); KeyError for any other variable it lacks."""
    auxiliary = set(problem.model.auxiliary_names)
    names = problem.variables.names
    x = np.array([values[name] if name in values or name not in auxiliary else 0.0 for name in names], dtype=float)
    if all(name in values for name in names):
        return x
    tight = problem.scale(tight_bounds(problem, problem.unscale(x)))
    return np.array([x[i] if name in values else tight[i] for i, name in enumerate(names)], dtype=float)
