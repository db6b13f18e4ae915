"""Plain-text tables of a design (:class:`~springbalance.design.evaluated.EvaluatedDesign`): springs, per-joint
torques, objectives, clearance, failures and warnings."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from springbalance.design.clearance import FitRecord
from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.joint_hold import JointHold
from springbalance.design.solvers import FEASIBILITY_TOLERANCE
from springbalance.design.spring_mass import SpringMass
from springbalance.design.standard_wire import WireRounding
from springbalance.results.clearance import checked_clearance
from springbalance.results.flags import Flag, flags
from springbalance.results.pseudo_base_report import pseudo_base_lines
from springbalance.results.tolerance_report import tolerance_lines
from springbalance.results.verification_report import verification_lines
from springbalance.springs.laws import Spring


def result_table(result: EvaluatedDesign) -> str:
    """What the actuators still carry, before/after, plus the spring design.

    The sections, in order: the header (:func:`header_lines`), the springs (:func:`spring_lines`), what
    rounding the wires and fitting to the arm cost (:func:`wire_rounding_lines`, :func:`fit_lines`), what each seed gave
    when the design was solved at several (:func:`seed_search_lines`), the
    helical sizing (:func:`helical_sizing_lines`), the springs' mass (:func:`spring_mass_lines`), the pseudo-bases'
    mass and weight (:func:`~springbalance.results.pseudo_base_report.pseudo_base_lines`), the torque and
    objective tables (:func:`torque_lines`), the balance statement, the scenarios, the clearance table, the
    verification at unseen poses (:func:`~springbalance.results.verification_report.verification_lines`), the
    tolerances (:func:`~springbalance.results.tolerance_report.tolerance_lines`), the failures and the warnings (:func:`warning_lines`).
    """
    metrics = result.metrics()
    problem = result.problem
    lines = header_lines(result)
    lines.append("")
    lines.extend(spring_lines(result))
    lines.extend(wire_rounding_lines(result.wire_rounding, getattr(result, "wire_sizes", None)))
    lines.extend(joint_hold_lines(result.joint_hold))
    lines.extend(seed_search_lines(result))
    lines.extend(fit_lines(result.fit))
    lines.extend(helical_sizing_lines(result))
    lines.extend(spring_mass_lines(result))
    lines.extend(pseudo_base_lines(result))
    lines.append("")
    lines.extend(torque_lines(metrics))
    lines.append("\n  " + balance_statement(result))
    if getattr(problem, "scenarios", None):
        lines.extend(scenario_lines(result))
    if metrics["max_violation"] > FEASIBILITY_TOLERANCE:
        lines.append(
            f"\n  INFEASIBLE: largest constraint violation {metrics['max_violation']:.3g} "
            f"(tolerance {FEASIBILITY_TOLERANCE:g})"
        )
    lines.append("")
    lines.extend(clearance_section(result))
    lines.extend(verification_lines(result))
    lines.extend(tolerance_lines(result))
    lines.extend(warning_lines(flags(result)))
    return "\n".join(lines)


def header_lines(result: EvaluatedDesign) -> list[str]:
    """The first line (mechanism, samples, objective, status) and the multi-start's spread of objectives."""
    problem = result.problem
    lines = [
        f"springbalance: {problem.mechanism.name}, {problem.workspace.size} samples, "
        f"objective {problem.objective.name}, status: {result.status}"
    ]
    spread = result.spread()
    if spread.get("starts", 0) > 1:
        lines.append(
            f"multi-start: {spread['feasible']}/{spread['starts']} feasible, objective best "
            f"{spread.get('best', float('nan')):.6g}, median {spread.get('median', float('nan')):.6g}, "
            f"worst {spread.get('worst', float('nan')):.6g}"
        )
    return lines


def spring_lines(result: EvaluatedDesign) -> list[str]:
    """The "Springs" section: per spring its anchors [m] (or joint), parameter values, spec sheet or mass
    [kg], and the range of its length [m] and force [N] (angle [rad] and torque [N·m]) over the workspace."""
    lines = ["Springs (anchor points in body frames) [m]"]
    evaluation = result.evaluation
    for column, record in enumerate(result.springs):
        lines.extend(
            _spring_lines(
                result.problem.springs[column], record, evaluation.lengths[:, column], evaluation.tensions[:, column]
            )
        )
    return lines


def _spring_lines(spring: Spring, record: dict[str, Any], states: np.ndarray, forces: np.ndarray) -> list[str]:
    """One spring of the "Springs" section (``record``: its entry of ``EvaluatedDesign.springs``)."""
    part = f", stock part {record['part_number']}" if "part_number" in record else ""
    ideal = ", ideal" if record.get("ideal") else ""
    lines = [f"  {record['name']} ({record['type']}{ideal}{part})"]
    for end in spring.anchors:
        point = ", ".join(f"{v:+.4f}" for v in record[end]["point"])
        lines.append(
            f"    {end + ':':<5s} {record[end]['body']:<18s} [{point}]"
            + (f"  pulley r = {record[end]['pulley']['radius'] * 1e3:.4g} mm" if "pulley" in record[end] else "")
        )
    if "joint" in record:
        lines.append(f"    joint: {record['joint']}")
    # a count or a ratio (unit "1", such as active_coils) is printed bare: no unit after its number
    parameters = "  ".join(
        f"{key} {record[key]:.6g}" + ("" if unit == "1" else f" {unit}") for key, unit in spring.parameter_units.items()
    )
    lines.append(f"    {parameters}")
    if "helical" in record:
        lines.extend(f"    {line}" for line in spec_sheet_lines(record["helical"]))
    elif "mass" in record:
        wire = (
            f" (wire diameter {1e3 * record['wire_diameter']:.3g} mm for this rate)"
            if "wire_diameter" in record
            else ""
        )
        lines.append(f"    spring mass {record['mass']:.4g} kg, half at each end{wire}")
    (state, state_unit), (force, force_unit) = spring.state_quantity, spring.force_quantity
    lines.append(
        f"    {state} {states.min():.4f} … {states.max():.4f} {state_unit}   "
        f"{force} {forces.min():.4g} … {forces.max():.4g} {force_unit}"
    )
    return lines


def wire_rounding_lines(rounding: WireRounding | None, sizes: tuple[float, ...] | None = None) -> list[str]:
    """What rounding the coils' wires to standard sizes did [mm] and cost (empty when nothing was rounded); with
    ``sizes``, the design's ``solve.wire_sizes`` [m], it says they were the sizes."""
    if rounding is None:
        return []
    wires = ", ".join(f"{name} {1e3 * pair[0]:.3f} → {1e3 * pair[1]:.2f} mm" for name, pair in rounding.wires.items())
    series = f" (of solve.wire_sizes, {len(sizes)} sizes)" if sizes else ""
    lines = [
        f"  standard wire{series}: {wires or 'none rounded'}; objective {rounding.continuous_objective:.6g} → "
        f"{rounding.objective:.6g} ({rounding.cost_percent:+.2f} %)"
    ]
    lines.extend(f"  wire of {name} left continuous: {reason}" for name, reason in rounding.unrounded.items())
    return lines


def seed_search_lines(result: EvaluatedDesign) -> list[str]:
    """What each seed gave when the design was solved at several, and which was kept (empty for one seed)."""
    search = getattr(result, "seed_search", None)  # a DesignResult's (results.seed_search.SeedSearch)
    return [] if search is None else search.lines(result.problem.objective.unit)


def joint_hold_lines(hold: JointHold | None) -> list[str]:
    """What holding the weighted joints within the bare arm's peaks did and cost (empty when no joint was
    carried worse)."""
    if hold is None:
        return []
    joints = ", ".join(hold.joints)
    if not hold.held:
        return [f"  {joints} carried worse than the bare arm; no design near it holds them within its peaks"]
    return [
        f"  {joints} held within the bare arm's peak(s) ({hold.seconds:.1f} s): objective "
        f"{hold.objective_before:.6g} → {hold.objective:.6g} ({hold.cost_percent:+.2f} %)"
    ]


def fit_lines(fit: FitRecord | None) -> list[str]:
    """What fitting the springs to the arm did and cost: rounds, objective, closest approach and mounting
    offsets [mm] (empty when the design was not fitted)."""
    if fit is None:
        return []
    closest = ", ".join(f"{name} {1e3 * value:.1f} mm" for name, value in fit.closest.items())
    mounts = ", ".join(f"{name} {1e3 * value:.2f} mm" for name, value in fit.mounts.items())
    lines = [
        f"  fitted to the arm in {fit.rounds_text} ({fit.rows} linearised rows, "
        f"{fit.seconds:.1f} s){'' if fit.converged else ' — NOT CONVERGED'}: objective "
        f"{fit.objective_before:.6g} → {fit.objective:.6g} ({fit.cost_percent:+.2f} %)"
    ]
    if closest:
        lines.append(f"  closest approach over {fit.poses} poses checked: {closest}")
    if mounts:
        lines.append(f"  mounted anchors off their surfaces by: {mounts}")
    return lines


def helical_sizing_lines(result: EvaluatedDesign) -> list[str]:
    """The "Helical springs" section: the helical springs that realise ideal ones (empty when none is sized)."""
    sizing = result.helical_sizing()
    if not sizing:
        return []
    lines = ["", "Helical springs (Shigley's Mechanical Engineering Design, ch. 10)"]
    for name, design in sizing.items():
        text = design.summary().splitlines()
        lines.append(f"  {name}: {text[0]}")
        lines.extend(f"    {line}" for line in text[1:])
    return lines


def spring_mass_statement(mass: SpringMass) -> tuple[str, str]:
    """Two sentences on the springs' mass [kg]: the total (each spring's, the bound), then how it compares with
    the arm's moving mass and with the floor of the coils that balance the arm exactly (docs/model.md §5.1)."""
    parts = ", ".join(f"{name} {value:.4g}" for name, value in mass.springs.items())
    bound = f"; max_spring_mass {mass.bound:.4g} kg" if mass.bound is not None else ""
    arm = f"{100 * mass.ratio_to_arm:.3g} %" if np.isfinite(mass.ratio_to_arm) else "—"
    floor = f"{mass.ratio_to_floor:.3g}×" if np.isfinite(mass.ratio_to_floor) else "—"
    return (
        f"spring mass {mass.total:.4g} kg ({parts} kg){bound}",
        f"{arm} of the arm's moving mass {mass.arm_moving_mass:.4g} kg; {floor} the floor {mass.floor:.4g} kg "
        f"of coils that balance it exactly (a swing of {mass.energy_swing:.4g} J of gravity energy, at most "
        f"{mass.energy_per_kg:.4g} J/kg in {mass.floor_material})",
    )


def spring_mass_lines(result: EvaluatedDesign) -> list[str]:
    """The springs' mass against the arm and the floor (:func:`spring_mass_statement`), indented."""
    first, second = spring_mass_statement(result.spring_mass())
    return [f"  {first}", f"    {second}"]


def torque_lines(metrics: dict[str, Any]) -> list[str]:
    """The tables of :meth:`~springbalance.design.evaluated.EvaluatedDesign.metrics`: per joint the peak and
    RMS torque [N·m or N] before/after with the reduction [%], then every objective before/after (the
    optimised one marked ``*``)."""
    header = f"  {'joint':<22s}{'peak before':>13s}{'peak after':>12s}{'Δ%':>8s}{'rms before':>13s}{'rms after':>12s}{'Δ%':>8s}"
    lines = ["Actuator torque (gravity only vs with springs)", header]
    for row in metrics["joints"]:
        lines.append(
            f"  {row['joint'] + ' [' + row['unit'] + ']':<22s}{row['peak_before']:13.4g}{row['peak_after']:12.4g}"
            f"{_percent(row['peak_reduction_percent'])}{row['rms_before']:13.4g}{row['rms_after']:12.4g}"
            f"{_percent(row['rms_reduction_percent'])}"
        )
    lines.append("")
    lines.append(f"  {'objective':<22s}{'before':>13s}{'after':>12s}{'Δ%':>8s}")
    for name, row in metrics["objectives"].items():
        mark = " *" if name == metrics["optimised"] else ""
        if np.isnan(row["before"]):
            lines.append(
                f"  {name + ' [' + row['unit'] + ']':<22s}{'—':>13s}{'—':>12s}{'':>8s}  (needs an ordered workspace)"
            )
            continue
        lines.append(
            f"  {name + ' [' + row['unit'] + ']':<22s}{row['before']:13.4g}{row['after']:12.4g}"
            f"{_percent(row['reduction_percent'])}{mark}"
        )
    return lines


#: the rows of a coil's spec sheet: (label, key, scale to the unit shown, unit, format)
SPEC_SHEET_ROWS = (
    ("material", "material", None, "", "s"),
    ("ends", "end_type", None, "", "s"),
    ("wire diameter d", "wire_diameter", 1e3, "mm", ".3f"),
    ("mean coil diameter D", "mean_diameter", 1e3, "mm", ".2f"),
    ("outer diameter", "outer_diameter", 1e3, "mm", ".2f"),
    ("index D/d", "index", 1.0, "", ".2f"),
    ("active coils n", "active_coils", 1.0, "", ".2f"),
    ("free length", "free_length", 1e3, "mm", ".1f"),
    ("body length", "body_length", 1e3, "mm", ".1f"),
    ("solid length", "solid_length", 1e3, "mm", ".1f"),
    ("initial tension", "initial_tension", 1.0, "N", ".4g"),
    ("rate k", "rate", 1.0, "N/m", ".5g"),
    ("largest load", "max_load", 1.0, "N", ".4g"),
    ("longest length", "longest_length", 1e3, "mm", ".1f"),
    ("shortest length", "shortest_length", 1e3, "mm", ".1f"),
    ("largest stress", "max_stress", 1e-6, "MPa", ".0f"),
    ("allowable stress", "allowable_stress", 1e-6, "MPa", ".0f"),
    ("hook bending stress", "hook_bending_stress", 1e-6, "MPa", ".0f"),
    ("hook bending allowable", "hook_bending_allowable", 1e-6, "MPa", ".0f"),
    ("hook torsion stress", "hook_torsion_stress", 1e-6, "MPa", ".0f"),
    ("hook torsion allowable", "hook_torsion_allowable", 1e-6, "MPa", ".0f"),
    ("mass", "mass", 1.0, "kg", ".4g"),
)


def spec_sheet_rows(sheet: dict[str, Any]) -> list[tuple[str, str]]:
    """``(label, value with unit)`` of every entry a coil's spec sheet has."""
    rows = []
    for label, key, scale, unit, style in SPEC_SHEET_ROWS:
        if key not in sheet:
            continue
        value = sheet[key] if scale is None else sheet[key] * scale
        rows.append((label, f"{value:{style}} {unit}".strip()))
    return rows + fatigue_rows(sheet)


def fatigue_rows(sheet: dict[str, Any]) -> list[tuple[str, str]]:
    """``(label, value)`` of a coil's duty and its fatigue safety factor per location (docs/model.md §3.8.2)."""
    fatigue, duty = sheet.get("fatigue"), sheet.get("duty")
    if not fatigue or not duty:
        return []
    cycles = duty["cycles"] if isinstance(duty["cycles"], str) else f"{duty['cycles']:.0e}"
    rows = [
        (
            "duty",
            f"{cycles} cycles, n_f ≥ {duty['safety_factor']:g}, {duty['criterion']}"
            f"{', peened' if duty['peened'] else ''}, reliability {duty['reliability']:g}"
            + ("" if duty.get("stated", True) else " (assumed: the coil states no duty; checked, not designed for)"),
        ),
        ("load range", f"{fatigue['min_load']:.4g}–{fatigue['max_load']:.4g} N"),
    ]
    for key, margin in fatigue.items():
        if not isinstance(margin, dict):
            continue
        factor = "∞" if margin["safety_factor"] is None else f"{margin['safety_factor']:.2f}"
        rows.append(
            (f"fatigue n_f, {key.replace('_', ' ')}", f"{factor} ({margin['source']}); lives {margin['life_text']}")
        )
    return rows


def spec_sheet_lines(sheet: dict[str, Any]) -> list[str]:
    """The spec sheet of a coil as text, ending with its buildable verdict and every failed rule."""
    verdict = "BUILDABLE" if sheet["buildable"] else "NOT BUILDABLE: " + "; ".join(sheet["reasons"])
    lines = [f"{sheet['type']} spring: {verdict}"]
    rows = spec_sheet_rows(sheet)
    width = max(len(label) for label, _ in rows)
    lines.extend(f"  {label:<{width}s}  {value}" for label, value in rows)
    return lines


def clearance_section(result: EvaluatedDesign) -> list[str]:
    """The clearance table of the text report (empty without collision geometry)."""
    report = checked_clearance(result)
    return [] if report is None else report.lines() + [""]


def warning_lines(flags: Sequence[Flag]) -> list[str]:
    """The findings: a "Failures (n)" section first when there are failures, then "Warnings (n)", one
    entry per flag (kind, message, hint); "Warnings: none" when there is no warning."""
    lines: list[str] = []
    failed = [flag for flag in flags if flag.failure]
    warned = [flag for flag in flags if not flag.failure]
    if failed:
        lines.append(f"Failures ({len(failed)}): this design does not pass")
        lines.extend(_flag_lines(failed))
        lines.append("")
    if not warned:
        return lines + ["Warnings: none"]
    lines.append(f"Warnings ({len(warned)})")
    return lines + _flag_lines(warned)


def _flag_lines(flags: Sequence[Flag]) -> list[str]:
    lines = []
    for flag in flags:
        lines.append(f"  [{flag.kind}] {flag.message}")
        if flag.hint:
            lines.append(f"    hint: {flag.hint}")
    return lines


def balance_statement(result: EvaluatedDesign) -> str:
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
            potential = (
                f"; total potential constant within each scenario at {levels} J "
                f"(largest spread {balance['potential_spread']:.2g} J)"
            )
        else:
            potential = f"; total potential constant at {balance['potential']:.6g} J (spread {balance['potential_spread']:.2g} J)"
        return (
            f"Exactly balanced{joints}: residual torque ≤ {balance['residual']:.3g} {unit} "
            f"({balance['relative_residual']:.2g} of the unbalanced peak) at every sample{potential}"
        )
    return f"Largest residual torque{joints}: {100 * balance['relative_residual']:.3g} % of the unbalanced peak"


def scenario_lines(result: EvaluatedDesign) -> list[str]:
    """Per scenario of a multi-scenario design: payload, per-scenario variables, peak and RMS residual."""
    problem = result.problem
    rows = problem.scenario_table(result.x)
    names = list(rows[0]["variables"]) if rows else []
    shared = "every variable shared" if not names else f"per-scenario variables: {', '.join(problem.per_scenario)}"
    lines = [
        "",
        f"Scenarios ({len(rows)}, objective aggregated as {problem.aggregate!r}; {shared}; "
        "the tables above cover all scenarios' samples)",
        f"  {'scenario':<18s}{'payload [kg]':>13s}"
        + "".join(f"{name:>26s}" for name in names)
        + f"{'peak [N·m]':>13s}{'rms [N·m]':>12s}",
    ]
    for row in rows:
        values = "".join(f"{row['variables'][name]:26.6g}" for name in names)
        lines.append(f"  {row['name']:<18s}{row['payload']:13.4g}{values}{row['peak']:13.4g}{row['rms']:12.4g}")
    return lines


def _percent(value: float) -> str:
    return f"{'—':>8s}" if not np.isfinite(value) else f"{value:8.1f}"
