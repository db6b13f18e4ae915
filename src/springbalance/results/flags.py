"""Findings about a design: failures (the design must not pass as fine) and warnings (things a report
should point out before the design is built).

:func:`flags` inspects a design (:class:`~springbalance.design.evaluated.EvaluatedDesign`) and returns one
:class:`~springbalance.results.flag.Flag` per finding, failures first; each has a ``severity``,
``"failure"`` or ``"warning"``. :data:`CHECKS` lists the functions that find them (one per kind or
two; a new kind is one more function there). The failures:

- ``infeasible``, ``not_converged``, ``overlap``, ``partial``: see :mod:`springbalance.results.failure_flags`.
- ``unbuildable``: a helical coil spring whose spec sheet fails a rule (stress, index, initial
  tension, envelope, solid length, buckling); its ``reasons`` name every failed rule.
- ``worse_joint`` on a joint of weight > 0: see below.

The warnings:

- ``at_bound``: a design variable ended at (within ``1e-6`` of its range of) one of its bounds,
  so the optimum probably lies beyond it; the hint says which bound to move and which way.
  Variables whose lower and upper bounds are equal are not variables and are skipped.
- ``worse_joint`` on a joint of weight 0 (a failure on a joint of weight > 0): a joint whose peak or
  RMS torque with the springs exceeds its torque without them (gravity only, docs/model.md §4).
  Differences below ``1e-9`` of the largest unbalanced peak are round-off, so a joint that gravity
  does not load is flagged only when the springs load it by more than that.
- ``law``: a spring whose real part departs from its idealised law somewhere in the workspace
  (slack, beyond its stroke, outside its length range or table), as reported by each law's
  ``law_warnings`` through :func:`springbalance.io.export.law_warnings`.
- ``unbuildable_ideal``: an ideal extension or compression spring (not a gas spring) for which
  :func:`springbalance.springs.sizing.size_helical_spring` finds no helical spring: of music
  wire, or of the material of the spring's ``helical`` option when it has one.
- ``unbuildable``: a helical coil spring whose spec sheet fails a rule (stress, index, initial
  tension, envelope, solid length, buckling); its ``reasons`` name every failed rule.
- ``heavy_springs``: the springs together weigh more than :data:`HEAVY_ARM_FRACTION` of the arm's moving
  mass or more than :data:`HEAVY_FLOOR_RATIO` times the floor of the coils that balance it exactly
  (:mod:`springbalance.design.spring_mass`, docs/model.md §5.1); the hint points at ``max_spring_mass``.
- ``not_verified`` (a failure): a rule the design breaks at poses it was not optimised on, or a peak
  objective's residual too far above its sampled value there (the design's verification,
  :mod:`springbalance.design.verification`); one flag per rule.
- ``inside_own_link`` (a warning): a two-point spring whose centre line runs inside its own anchor link
  beyond its anchor (:mod:`springbalance.results.own_link`; only with collision geometry).
- ``weak_design``: see :mod:`springbalance.results.weak_design`.
- ``beyond_joint_limits``, ``off_series_wire``: see :mod:`springbalance.results.range_flags`.
- ``arm_through_floor``: see :mod:`springbalance.results.floor_flags`.
- ``short_life``: a coil without a stated duty that would not live the default one; see
  :mod:`springbalance.results.fatigue_flags`.
- ``long_bracket``: an anchor that stands far off its link (a bracket the design leaves out); see
  :mod:`springbalance.results.brackets`.

The text report, ``report.html`` and ``design.json`` all list them, failures first (``design.json``:
every finding under ``warnings``, the failures again under ``failures``).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.problem import DesignProblem
from springbalance.design.worse_joints import TORQUE_TOLERANCE
from springbalance.errors import InputError
from springbalance.export.common import law_warnings, spring_name
from springbalance.results.brackets import long_bracket_flags
from springbalance.results.failure_flags import infeasible_flags, not_converged_flags, overlap_flags, partial_flags
from springbalance.results.fatigue_flags import short_life_flags
from springbalance.results.flag import FAILURE, WARNING, Flag, failures_first
from springbalance.results.floor_flags import arm_through_floor_flags
from springbalance.results.own_link import inside_own_link
from springbalance.results.range_flags import beyond_joint_limits_flags, off_series_wire_flags
from springbalance.results.rules import BOUND_TOLERANCE, at_bounds
from springbalance.results.verification_report import margin_text, pose_text
from springbalance.results.weak_design import weak_design_flags
from springbalance.springs import CompressionSpring, ExtensionSpring, GasSpring
from springbalance.springs.sizing import size_helical_spring

#: material of the helical springs that ``unbuildable_ideal`` tries (springs without a ``helical`` option)
DEFAULT_MATERIAL = "music_wire"

#: the kinds of finding and their severity (``worse_joint``: a failure on a joint of weight > 0)
KINDS = {
    "infeasible": FAILURE,
    "not_converged": FAILURE,
    "unbuildable": FAILURE,
    "overlap": FAILURE,
    "partial": FAILURE,
    "worse_joint": FAILURE,
    "at_bound": WARNING,
    "law": WARNING,
    "unbuildable_ideal": WARNING,
    "weak_design": WARNING,
    "beyond_joint_limits": WARNING,
    "arm_through_floor": WARNING,
    "off_series_wire": WARNING,
    "heavy_springs": WARNING,
    "not_verified": FAILURE,
    "inside_own_link": WARNING,
    "short_life": WARNING,
    "long_bracket": WARNING,
}
#: ``heavy_springs``: the springs are heavy above this fraction of the arm's moving mass [1] ...
HEAVY_ARM_FRACTION = 0.10
#: ... or above this multiple of the floor of the coils that balance the arm exactly [1]
HEAVY_FLOOR_RATIO = 4.0


def flags(result: EvaluatedDesign) -> list[Flag]:
    """Every finding about ``result``: the flags of each of :data:`CHECKS`, failures first."""
    return failures_first(flag for check in CHECKS for flag in check(result))


def failures(result: EvaluatedDesign) -> list[Flag]:
    """The failures among :func:`flags` (empty: the design passes)."""
    return [flag for flag in flags(result) if flag.failure]


# ---------------------------------------------------------------------- at_bound
def _quantity(value: float, unit: str) -> str:
    return f"{value:.6g}" if unit in ("", "1") else f"{value:.6g} {unit}"


def _nonnegative_parameter(problem: DesignProblem, name: str) -> str | None:
    """The law whose parameter ``name`` (``spring.key``, maybe ``[scenario]``) must be ≥ 0, else None."""
    base = name.split("[", 1)[0]
    for spring in problem.springs:
        for key in getattr(spring, "nonnegative", ()):
            if base == f"{spring.name}.{key}":
                return spring.kind
    return None


def at_bound_flags(result: EvaluatedDesign, tolerance: float = BOUND_TOLERANCE) -> list[Flag]:
    """Design variables at (within ``tolerance`` of their range of) a bound; fixed ones are skipped."""
    found = []
    for name, unit, side, bound, value in at_bounds(result, tolerance):
        direction = "raise" if side == "upper" else "lower"
        message = f"{name} = {_quantity(value, unit)} is at its {side} bound {_quantity(bound, unit)}"
        law = _nonnegative_parameter(result.problem, name)
        if side == "lower" and bound <= 0 and law is not None:
            hint = (
                f"{name} cannot go below 0 ({law} law): the optimum wants less of it; free other "
                "variables (anchors, free length) or try another spring law"
            )
        else:
            hint = f"{direction} {name}'s {side} bound ({_quantity(bound, unit)})"
            if name.split("[", 1)[0].endswith(".s") and unit == "1":
                hint += ", or extend the segment " + ("past its end" if side == "upper" else "before its start")
        found.append(Flag("at_bound", name, message, hint))
    return found


# ---------------------------------------------------------------------- worse_joint
def worse_joint_flags(result: EvaluatedDesign, tolerance: float = TORQUE_TOLERANCE) -> list[Flag]:
    """Joints whose peak or RMS torque is larger with the springs than without them
    (:mod:`springbalance.design.worse_joints`): a failure on a joint of weight > 0
    (the design was asked to balance it), a warning on one of weight 0."""
    weights = dict(zip((joint.name for joint in result.problem.mechanism.joints), result.problem.weights.tolist()))
    found = []
    for row in result.joints_made_worse(tolerance):
        worse = row["worse"]
        unit = row["unit"]
        parts = [
            f"{label} {row[key + '_after']:.4g} {unit} with the springs vs {row[key + '_before']:.4g} {unit} without"
            for label, key in (("peak", "peak"), ("RMS", "rms"))
            if label in worse
        ]
        message = f"joint {row['joint']} carries more torque with the springs than without: " + "; ".join(parts)
        weighted = weights.get(row["joint"], 1.0) > 0
        if not weighted:
            hint = (
                f"{row['joint']} has weight 0, so the objective ignores it: give it a weight > 0, or move the "
                "springs that act across it"
            )
        else:
            hint = (
                f"move or soften the springs that act across {row['joint']}, raise its weight in the objective, or "
                "set no_joint_worse: true (each weighted joint held within what the bare arm carries)"
            )
        found.append(Flag("worse_joint", row["joint"], message, hint, FAILURE if weighted else WARNING))
    return found


# ---------------------------------------------------------------------- law
def _law_hint(message: str) -> str:
    if "keep_tension is false" in message:
        return "turn keep_tension on (the default) so that the solver keeps L ≥ l0, or lower the free length"
    if "shorter than its free length" in message:
        return "lower the free length or move the anchors so that the spring stays stretched"
    if "longer than its free length" in message:
        return "turn stays_compressed on (the default), raise the free length or move the anchors"
    if "beyond its stroke" in message:
        return "choose a longer stroke or move the anchors"
    if "leaves its table" in message:
        return "extend the table over the lengths the workspace visits, or keep stays_in_table on"
    if "length range" in message:
        return "widen min_length / max_length, or solve again so that the design meets them"
    return "check the spring's working range"


def law_flags(result: EvaluatedDesign) -> list[Flag]:
    """Springs whose real law departs from the idealised one in the workspace (one flag per case)."""
    names = sorted((spring_name(spring) for spring in result.problem.springs), key=len, reverse=True)
    found = []
    for message in law_warnings(result):
        subject = next((name for name in names if message.startswith(f"spring {name!r}")), "springs")
        found.append(Flag("law", subject, message, _law_hint(message)))
    return found


# ---------------------------------------------------------------------- unbuildable_ideal
def unbuildable_flags(result: EvaluatedDesign, material: str = DEFAULT_MATERIAL) -> list[Flag]:
    """Extension and compression springs (not gas springs, k > 0) that no helical spring realises.

    Inputs to :func:`~springbalance.springs.sizing.size_helical_spring` per spring: its rate, free
    length, longest and shortest length and largest force magnitude over the workspace, as in
    :meth:`~springbalance.design.evaluated.EvaluatedDesign.helical_sizing`. A spring with a ``helical``
    option is sized with its own material, any other with ``material``.
    """
    problem, evaluation = result.problem, result.evaluation
    found = []
    for column, spring in enumerate(problem.springs):
        if not isinstance(spring, (ExtensionSpring, CompressionSpring)) or isinstance(spring, GasSpring):
            continue
        kind = getattr(spring, "helical_kind", None)
        if kind is None:
            continue
        values = problem.model.spring_values(spring, result.x)
        stiffness, free_length = float(values["stiffness"]), float(values["free_length"])
        if not stiffness > 0:
            continue
        option = getattr(spring, "helical", None)
        chosen = option.material if option is not None else material
        lengths, forces = evaluation.lengths[:, column], evaluation.tensions[:, column]
        max_force = float(np.max(np.abs(forces)))
        try:
            design = size_helical_spring(
                stiffness,
                free_length,
                float(np.max(lengths)),
                max_force,
                material=chosen,
                kind=kind,
                min_length=float(np.min(lengths)),
            )
            feasible, reasons = design.feasible, list(design.reasons)
        except InputError as error:
            feasible, reasons = False, [str(error)]
        if feasible:
            continue
        material_name = getattr(chosen, "name", chosen)
        message = (
            f"spring {spring.name!r} ({spring.kind}, k {stiffness:.4g} N/m, l0 {free_length:.4g} m, "
            f"lengths {float(np.min(lengths)):.4g}–{float(np.max(lengths)):.4g} m, largest force "
            f"{max_force:.4g} N): no helical {kind} spring of {material_name} realises it: " + "; ".join(reasons)
        )
        hint = (
            "lower the stiffness or the force, lengthen the free length, or give the spring a helical option "
            "so that the optimisation keeps it buildable"
        )
        found.append(Flag("unbuildable_ideal", spring_name(spring), message, hint))
    return found


def unbuildable_coil_flags(result: EvaluatedDesign) -> list[Flag]:
    """Helical coil springs whose spec sheet fails a rule (the solver's constraints not met)."""
    found = []
    for record in result.springs:
        sheet = record.get("helical")
        if sheet is not None and not sheet["buildable"]:
            found.append(
                Flag(
                    "unbuildable",
                    record["name"],
                    f"spring {record['name']!r} ({sheet['type']}) cannot be built: " + "; ".join(sheet["reasons"]),
                    "widen the coil's bounds (wire, coil diameter, coils, envelope) or move its anchors so "
                    "that it stretches less; more starts may find a feasible coil",
                    FAILURE,
                )
            )
    return found


# ---------------------------------------------------------------------- heavy_springs
def heavy_springs_flags(result: EvaluatedDesign) -> list[Flag]:
    """The springs' total mass above :data:`HEAVY_ARM_FRACTION` of the arm's moving mass or above
    :data:`HEAVY_FLOOR_RATIO` times the floor (:meth:`~springbalance.design.evaluated.EvaluatedDesign.spring_mass`)."""
    mass = result.spring_mass()
    to_arm, to_floor = mass.ratio_to_arm, mass.ratio_to_floor
    if not (to_arm > HEAVY_ARM_FRACTION or to_floor > HEAVY_FLOOR_RATIO):  # a NaN ratio never flags
        return []
    arm = f"{100 * to_arm:.3g} %" if to_arm == to_arm else "—"  # NaN: an arm without moving mass
    floor = f"{to_floor:.3g}×" if to_floor == to_floor else "—"  # NaN: no swing of gravity energy
    message = (
        f"the springs weigh {mass.total:.4g} kg: {arm} of the arm's moving mass {mass.arm_moving_mass:.4g} kg "
        f"(warned above {100 * HEAVY_ARM_FRACTION:g} %), {floor} the floor {mass.floor:.3g} kg of coils that "
        f"balance it exactly (warned above {HEAVY_FLOOR_RATIO:g}×)"
    )
    hint = (
        "bound the springs' total mass with max_spring_mass [kg] (docs/model.md §5.1); a spring that works "
        "over more of its stroke, nearer its allowable stress, carries the same energy with less wire"
    )
    return [Flag("heavy_springs", "springs", message, hint)]


# ---------------------------------------------------------------------- not_verified, inside_own_link
def verification_hint(mode: str, rounds: int, rule: str) -> str:
    """What to do about a rule (``"clearance"``, a coil's rule, ``"residual"``) broken at unseen poses, after a
    verification in ``mode`` that made ``rounds`` re-solves (in mode ``"resolve"``, 0 when no re-solve from the
    design met the added poses)."""
    if mode != "resolve":
        return (
            "solve with verify='resolve' (the worst poses join the samples and the design is solved again), "
            "or use more workspace samples"
        )
    tried = (
        f"{rounds} re-solve(s) with the worst poses added did not clear it"
        if rounds
        else "no re-solve from the design could meet the rules at the poses added"
    )
    if rule == "clearance":
        return (
            f"{tried}: from where the spring lies it cannot pass clear of the link at that pose. Narrow the "
            "workspace near that pose (the arm may fold onto itself there), move the spring's anchor boxes, or "
            "raise clearance.check_samples, so that the fit meets such poses while the anchors can still move"
        )
    return f"{tried}: use more workspace samples"


def not_verified_flags(result: EvaluatedDesign) -> list[Flag]:
    """Rules the design breaks at unseen poses, and a peak residual above its allowance there (its verification)."""
    record = result.verification
    if record is None or record.passed:
        return []
    units = {joint.name: joint.unit for joint in result.problem.mechanism.joints}
    found = [
        Flag(
            "not_verified",
            rule.label,
            f"{rule.label} is broken at unseen poses: margin {margin_text(rule.margin, rule.unit)} at "
            f"{pose_text(rule.pose, units, rule.scenario)} (worst at the samples "
            f"{margin_text(rule.sampled, rule.unit)}; {record.poses} poses verified)",
            verification_hint(record.mode, record.rounds, rule.rule),
            severity=FAILURE,
        )
        for rule in record.violated
    ]
    if not record.residual_passed:
        found.append(
            Flag(
                "not_verified",
                record.objective,
                f"objective {record.objective} is {record.objective_dense:.4g} at unseen poses, "
                f"{record.objective_sampled:.4g} at the samples",
                verification_hint(record.mode, record.rounds, "residual"),
                severity=FAILURE,
            )
        )
    return found


def inside_own_link_flags(result: EvaluatedDesign) -> list[Flag]:
    """Springs whose centre line runs inside their own anchor link beyond the anchor (with collision geometry)."""
    units = {joint.name: joint.unit for joint in result.problem.mechanism.joints}
    return [
        Flag(
            "inside_own_link",
            f"{found.spring}.{found.end}",
            f"spring {found.spring!r} runs inside its own anchor link {found.body!r} beyond its anchor (end "
            f"{found.end}): its centre line lies {1e3 * found.depth:.1f} mm deep inside at "
            f"{pose_text(found.pose, units, found.scenario)}",
            f"move the anchor on {found.body} to its surface, or the spring's other anchor, so that the spring "
            "leaves the link outward; the clearance check exempts a spring's own links",
        )
        for found in inside_own_link(result)
    ]


#: the checks :func:`flags` runs, in order; each takes a design and returns its flags
CHECKS: tuple[Callable[[EvaluatedDesign], list[Flag]], ...] = (
    partial_flags,
    infeasible_flags,
    not_converged_flags,
    unbuildable_coil_flags,
    overlap_flags,
    not_verified_flags,
    at_bound_flags,
    worse_joint_flags,
    law_flags,
    unbuildable_flags,
    weak_design_flags,
    beyond_joint_limits_flags,
    arm_through_floor_flags,
    off_series_wire_flags,
    short_life_flags,
    heavy_springs_flags,
    inside_own_link_flags,
    long_bracket_flags,
)
