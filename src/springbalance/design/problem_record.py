"""A design problem's options beyond its objective and weights, as a saved design records them: scenarios,
``no_joint_worse``, the bound on the springs' mass and the clearance (``design.json``, key ``problem``)."""

from __future__ import annotations

from typing import Any, Sequence

from springbalance.design.clearance import Clearance
from springbalance.design.problem_inputs import spring_mass_bound
from springbalance.design.scenarios import Scenario


def options_record(
    scenarios: Sequence[Scenario],
    per_scenario: Sequence[str],
    aggregate: str,
    no_joint_worse: bool,
    max_spring_mass: float | None,
    clearance: Clearance | None,
) -> dict:
    """``{"scenarios": {cases, per_scenario, aggregate}}`` with scenarios, ``"no_joint_worse": true``,
    ``max_spring_mass`` [kg] and ``clearance`` when set (``{}`` when none)."""
    record: dict[str, Any] = {"no_joint_worse": True} if no_joint_worse else {}
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
    aggregate, no_joint_worse, clearance, max_spring_mass) from what :func:`options_record` wrote."""
    found: dict[str, Any] = {"no_joint_worse": True} if record.get("no_joint_worse") else {}
    if record.get("max_spring_mass") is not None:
        found["max_spring_mass"] = spring_mass_bound(record["max_spring_mass"], "design max_spring_mass")
    if record.get("clearance"):
        found["clearance"] = Clearance.from_dict(record["clearance"], "design clearance")
    saved = record.get("scenarios")
    if not saved:
        return found
    return {
        "scenarios": [Scenario.from_dict(case) for case in saved["cases"]],
        "per_scenario": saved.get("per_scenario", []),
        "aggregate": saved.get("aggregate", "sum"),
        **found,
    }
