"""A design problem's options beyond its objective and weights, as a saved design records them: scenarios,
``no_joint_worse``, the bound on the springs' mass, the clearance and a robust design's tolerance
(``design.json``, key ``problem``); and the per-scenario table of a design."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from springbalance.design.clearance import Clearance
from springbalance.design.problem_inputs import spring_mass_bound
from springbalance.design.scenarios import Scenario
from springbalance.design.tolerance_spec import ToleranceSpec


def options_record(
    scenarios: Sequence[Scenario],
    per_scenario: Sequence[str],
    aggregate: str,
    no_joint_worse: bool,
    max_spring_mass: float | None,
    clearance: Clearance | None,
    robust: ToleranceSpec | None = None,
) -> dict:
    """``{"scenarios": {cases, per_scenario, aggregate}}`` with scenarios, ``"no_joint_worse": true``,
    ``max_spring_mass`` [kg], ``clearance`` and ``robust`` (the tolerance of a robust design) when set
    (``{}`` when none)."""
    record: dict[str, Any] = {"no_joint_worse": True} if no_joint_worse else {}
    if robust is not None:
        record["robust"] = robust.to_dict()
    if max_spring_mass is not None:
        record["max_spring_mass"] = max_spring_mass
    if clearance is not None:
        record["clearance"] = clearance.to_dict()
    if not scenarios:
        return record
    return {
        "scenarios": {
            "cases": [scenario.to_dict() for scenario in scenarios],
            "per_scenario": list(per_scenario),
            "aggregate": aggregate,
        },
        **record,
    }


def options(record: dict) -> dict:
    """Keyword arguments of :class:`~springbalance.design.problem.DesignProblem` (scenarios, per_scenario,
    aggregate, no_joint_worse, clearance, max_spring_mass, tolerance) from what :func:`options_record` wrote."""
    found: dict[str, Any] = {"no_joint_worse": True} if record.get("no_joint_worse") else {}
    if record.get("max_spring_mass") is not None:
        found["max_spring_mass"] = spring_mass_bound(record["max_spring_mass"], "design max_spring_mass")
    if record.get("clearance"):
        found["clearance"] = Clearance.from_dict(record["clearance"], "design clearance")
    if record.get("robust"):
        found["tolerance"] = ToleranceSpec.from_record(record["robust"], "design robust")
    saved = record.get("scenarios")
    if not saved:
        return found
    return {
        "scenarios": [Scenario.from_dict(case) for case in saved["cases"]],
        "per_scenario": saved.get("per_scenario", []),
        "aggregate": saved.get("aggregate", "sum"),
        **found,
    }


def scenario_rows(problem: Any, x: np.ndarray) -> list[dict]:
    """Per scenario of ``problem`` (a :class:`~springbalance.design.problem.DesignProblem`): name, payload [kg],
    per-scenario variable values, peak and RMS residual [N·m] (weighted, over all joints) of design ``x``."""
    if not problem.scenarios:
        return []
    tau = problem.evaluate(x).tau * problem.weights
    names = [problem.model.base_variables.names[i] for i in problem.model.per_scenario]
    rows = []
    for index, (scenario, block) in enumerate(zip(problem.scenarios, np.split(tau, len(problem.scenarios)))):
        base = problem.model.scenario_vector(x, index)
        rows.append(
            {
                "name": scenario.name,
                "payload": scenario.payload_mass,
                "variables": {name: float(base[i]) for name, i in zip(names, problem.model.per_scenario)},
                "peak": float(np.max(np.abs(block))),
                "rms": float(np.sqrt(np.mean(block**2))),
            }
        )
    return rows
