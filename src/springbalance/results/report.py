"""Plain-text tables of a design result (springs, per-joint torques, objectives)."""

from __future__ import annotations

import numpy as np

from springbalance.design.solvers import FEASIBILITY_TOLERANCE


def result_table(result) -> str:
    """What the actuators still carry, before/after, plus the spring design."""
    metrics = result.metrics()
    problem = result.problem
    lines = [f"springbalance: {problem.mechanism.name}, {problem.workspace.size} samples, "
             f"objective {problem.objective.name}, status: {result.status}"]
    spread = result.spread()
    if spread.get("starts", 0) > 1:
        lines.append(f"multi-start: {spread['feasible']}/{spread['starts']} feasible, objective best "
                     f"{spread.get('best', float('nan')):.6g}, median {spread.get('median', float('nan')):.6g}, "
                     f"worst {spread.get('worst', float('nan')):.6g}")
    lines.append("")
    lines.append("Springs (anchor points in body frames) [m]")
    evaluation = result.evaluation
    for column, record in enumerate(result.springs):
        spring = problem.springs[column]
        states, forces = evaluation.lengths[:, column], evaluation.tensions[:, column]
        lines.append(f"  {record['name']} ({record['type']})")
        for end in spring.anchors:
            point = ", ".join(f"{v:+.4f}" for v in record[end]["point"])
            lines.append(f"    {end}: {record[end]['body']:<18s} [{point}]")
        if "joint" in record:
            lines.append(f"    joint: {record['joint']}")
        parameters = "  ".join(f"{key} {record[key]:.6g} {unit}" for key, unit in spring.parameter_units.items())
        lines.append(f"    {parameters}")
        if "mass" in record:
            wire = f" (wire diameter {1e3 * record['wire_diameter']:.3g} mm for this rate)" if "wire_diameter" in record else ""
            lines.append(f"    spring mass {record['mass']:.4g} kg, half at each end{wire}")
        (state, state_unit), (force, force_unit) = spring.state_quantity, spring.force_quantity
        lines.append(f"    {state} {states.min():.4f} … {states.max():.4f} {state_unit}   "
                     f"{force} {forces.min():.4g} … {forces.max():.4g} {force_unit}")
    sizing = result.helical_sizing()
    if sizing:
        lines.append("")
        lines.append("Helical springs (Shigley's Mechanical Engineering Design, ch. 10)")
        for name, design in sizing.items():
            text = design.summary().splitlines()
            lines.append(f"  {name}: {text[0]}")
            lines.extend(f"    {line}" for line in text[1:])
    lines.append("")
    header = f"  {'joint':<22s}{'peak before':>13s}{'peak after':>12s}{'Δ%':>8s}{'rms before':>13s}{'rms after':>12s}{'Δ%':>8s}"
    lines.append("Actuator torque (gravity only vs with springs)")
    lines.append(header)
    for row in metrics["joints"]:
        lines.append(f"  {row['joint'] + ' [' + row['unit'] + ']':<22s}{row['peak_before']:13.4g}{row['peak_after']:12.4g}"
                     f"{_percent(row['peak_reduction_percent'])}{row['rms_before']:13.4g}{row['rms_after']:12.4g}"
                     f"{_percent(row['rms_reduction_percent'])}")
    lines.append("")
    lines.append(f"  {'objective':<22s}{'before':>13s}{'after':>12s}{'Δ%':>8s}")
    for name, row in metrics["objectives"].items():
        mark = " *" if name == metrics["optimised"] else ""
        if np.isnan(row["before"]):
            lines.append(f"  {name + ' [' + row['unit'] + ']':<22s}{'—':>13s}{'—':>12s}{'':>8s}  (needs an ordered workspace)")
            continue
        lines.append(f"  {name + ' [' + row['unit'] + ']':<22s}{row['before']:13.4g}{row['after']:12.4g}"
                     f"{_percent(row['reduction_percent'])}{mark}")
    lines.append("\n  " + balance_statement(result))
    if getattr(problem, "scenarios", None):
        lines.extend(scenario_lines(result))
    if metrics["max_violation"] > FEASIBILITY_TOLERANCE:
        lines.append(f"\n  INFEASIBLE: largest constraint violation {metrics['max_violation']:.3g} "
                     f"(tolerance {FEASIBILITY_TOLERANCE:g})")
    return "\n".join(lines)


def balance_statement(result) -> str:
    """One sentence: "Exactly balanced …" with the constant total potential, or the largest residual."""
    problem = result.problem
    balance = result.exact_balance()
    unit = "/".join(sorted({joint.torque_unit for joint in problem.mechanism.joints}))
    every_joint = bool(np.all(problem.weights > 0))
    joints = "" if every_joint else " on the joints with weight > 0"
    if balance["exact"]:
        if not every_joint:
            potential = ""
        elif len(balance["scenario_potentials"]) > 1:
            levels = ", ".join(f"{value:.6g}" for value in balance["scenario_potentials"])
            potential = (f"; total potential constant within each scenario at {levels} J "
                         f"(largest spread {balance['potential_spread']:.2g} J)")
        else:
            potential = f"; total potential constant at {balance['potential']:.6g} J (spread {balance['potential_spread']:.2g} J)"
        return (f"Exactly balanced{joints}: residual torque ≤ {balance['residual']:.3g} {unit} "
                f"({balance['relative_residual']:.2g} of the unbalanced peak) at every sample{potential}")
    return f"Largest residual torque{joints}: {100 * balance['relative_residual']:.3g} % of the unbalanced peak"


def scenario_lines(result) -> list[str]:
    """Per scenario of a multi-scenario design: payload, per-scenario variables, peak and RMS residual."""
    problem = result.problem
    rows = problem.scenario_table(result.x)
    names = list(rows[0]["variables"]) if rows else []
    shared = "every variable shared" if not names else f"per-scenario variables: {', '.join(problem.per_scenario)}"
    lines = ["", f"Scenarios ({len(rows)}, objective aggregated as {problem.aggregate!r}; {shared}; "
                 "the tables above cover all scenarios' samples)",
             f"  {'scenario':<18s}{'payload [kg]':>13s}" + "".join(f"{name:>26s}" for name in names) +
             f"{'peak [N·m]':>13s}{'rms [N·m]':>12s}"]
    for row in rows:
        values = "".join(f"{row['variables'][name]:26.6g}" for name in names)
        lines.append(f"  {row['name']:<18s}{row['payload']:13.4g}{values}{row['peak']:13.4g}{row['rms']:12.4g}")
    return lines


def _percent(value: float) -> str:
    return f"{'—':>8s}" if not np.isfinite(value) else f"{value:8.1f}"
