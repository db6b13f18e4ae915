r"""The robust design (``tolerance: {robust: true}``, docs/model.md §3.10): a design problem over the
corners of the springs' tolerance box, and what its design says per corner.

:func:`robust_cases` turns a :class:`~springbalance.design.tolerance_spec.ToleranceSpec` with
``robust`` into the problem's cases (:class:`~springbalance.design.tolerance_corners.LawCorners`): the
workspace is stacked once per case (the nominal law first, then the corners), and the objective is the
worst case over them (``aggregate: worst``, an epigraph solved by IPOPT), as for payload scenarios.
:func:`corner_table` reads a solved design: per corner, its peak and RMS residual and each spring's
adjuster setting [m], and whether the setting reached the travel bound.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from springbalance.design.objectives import Objective
from springbalance.design.scenarios import Scenario
from springbalance.design.tolerance_corners import LawCorners
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.errors import InputError
from springbalance.springs.laws import Spring

#: the objectives a robust design minimises the worst corner of (convex in the residual, docs/model.md §3.10)
ROBUST_OBJECTIVES = ("rms", "peak", "joint_peaks")
#: an adjuster setting within this fraction of the travel counts as at the bound
AT_BOUND = 1e-3


def checked_tolerance(tolerance: Any) -> ToleranceSpec | None:
    """``tolerance`` when it is a :class:`ToleranceSpec` or None; a one-line InputError otherwise."""
    if tolerance is not None and not isinstance(tolerance, ToleranceSpec):
        raise InputError(f"tolerance must be a springbalance ToleranceSpec or None, got {type(tolerance).__name__}")
    return tolerance


def robust_cases(
    tolerance: ToleranceSpec | None,
    springs: Sequence[Spring],
    objective: str | Objective,
    scenarios: Sequence[Any] | None,
    per_scenario: Sequence[str],
) -> LawCorners | None:
    """The corner cases of a robust ``tolerance`` (None when it is not robust), checked against the problem's
    other options: no payload scenarios, and an objective of :data:`ROBUST_OBJECTIVES`."""
    if tolerance is None or not tolerance.robust:
        return None
    if scenarios or per_scenario:
        raise InputError(
            "tolerance.robust: a robust design cannot also have scenarios or per_scenario variables; its corners "
            "are its scenarios"
        )
    name = objective.name if isinstance(objective, Objective) else str(objective)
    if name not in ROBUST_OBJECTIVES:
        raise InputError(
            f"tolerance.robust: objective {name!r} is not supported; use one of {', '.join(ROBUST_OBJECTIVES)}"
        )
    return LawCorners(tolerance, springs, tolerance.corners)


def case_scenarios(corners: LawCorners) -> list[Scenario]:
    """One (load-free) scenario per case: the workspace is repeated once per case."""
    return [Scenario(name) for name in corners.names]


def corner_table(problem: Any, x: np.ndarray) -> list[dict[str, Any]]:
    """Per case of a robust ``problem`` at design ``x``: ``name``, ``peak`` and ``rms`` of the weighted residual
    [N·m] and, with adjusters, ``adjusters`` (spring → setting [m]) and ``at_bound`` (the springs whose setting
    reached the travel); empty for a problem that is not robust."""
    corners: LawCorners | None = getattr(problem, "corners", None)
    if corners is None:
        return []
    travel = corners.spec.adjuster_travel
    tau = problem.evaluate(x).tau * problem.weights
    rows = []
    for s, (case, block) in enumerate(zip(corners.cases, np.split(tau, len(corners.cases)))):
        row: dict[str, Any] = {
            "name": case.name,
            "peak": float(np.max(np.abs(block))),
            "rms": float(np.sqrt(np.mean(block**2))),
        }
        if travel is not None:
            settings = {name: float(x[corners.adjusters[(name, s)]]) if s else 0.0 for name in corners.springs}
            row["adjusters"] = settings
            row["at_bound"] = [name for name, t in settings.items() if abs(t) >= travel * (1 - AT_BOUND)]
        rows.append(row)
    return rows


def nominal_design(problem: Any, x: np.ndarray) -> tuple[Any, np.ndarray]:
    """``(problem, x)`` of the nominal law: a robust problem's first case on its own (without the corners and
    the adjuster settings), else ``problem`` and ``x`` themselves."""
    if getattr(problem, "corners", None) is None:
        return problem, np.asarray(x, dtype=float)
    return problem.scenario_problem(0), problem.model.scenario_vector(x, 0)
