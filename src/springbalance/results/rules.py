"""The rules of a design's problem by name, with their margins at the design: which rule is violated,
which one binds.

A problem's rules are its constraint rows (:class:`~springbalance.design.torque_model.ConstraintBlock`:
a spring's practical constraints, such as a coil's ``body_stress``, and ``no_joint_worse.<joint>``), its
linear rows (:class:`~springbalance.design.clearance.LinearRows`: clearance from the links and mounted
anchors, labelled by the fit) and the bounds of its design variables. :func:`rule_margins` gives each
rule's smallest margin over the workspace samples: its row value (≥ 0 when it holds) in the row's
unit, and that value divided by the row's typical violation (its solver scale), so that rows of
different units compare. A rule *binds* (:func:`binding_rules`) when its scaled margin is at most
:data:`ACTIVE` (IPOPT meets an active row to about 1e-8 of its scale) or a variable sits within
:data:`BOUND_TOLERANCE` of its range of a bound.
"""

from __future__ import annotations

import dataclasses
import re
from typing import Iterator

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign

#: a rule whose margin is at most this fraction of its scale counts as binding
ACTIVE = 1e-3
#: a variable within this fraction of its range from a bound counts as at the bound
BOUND_TOLERANCE = 1e-6
#: the end of a linear row's label that names its pose and end: ``" (pose 0:17), end a"``
_POSE = re.compile(r" \(pose [^)]*\).*$")


@dataclasses.dataclass(frozen=True)
class RuleMargin:
    """One rule's smallest margin at a design.

    Attributes:
        rule: the rule, in words (``"s2: body stress"``, ``"s1 clear of forearm_link_0"``,
            ``"s1.wire_diameter at its upper bound"``).
        value: its smallest row value over the samples (negative: violated), in ``unit``.
        unit: the unit of ``value``.
        scaled: ``value`` divided by the row's typical violation (0 for a variable at a bound).
        linear: True for a rule of the linear rows (clearance, mounting).
    """

    rule: str
    value: float
    unit: str
    scaled: float
    linear: bool = False


def rule_margins(result: EvaluatedDesign) -> list[RuleMargin]:
    """Every constraint rule and linear rule of ``result``'s problem with its smallest margin, one entry per
    rule (the linear rows of one clearance pair or mounted anchor merged), smallest scaled margin first."""
    problem, evaluation = result.problem, result.evaluation
    found: dict[str, RuleMargin] = {}
    rows = evaluation.constraint_rows
    for block in getattr(problem.model, "constraint_blocks", []):
        if rows.size == 0 or block.offset >= rows.shape[1]:
            continue
        value = float(np.min(rows[:, block.offset]))
        rule = f"{block.spring}: {block.name.replace('_', ' ')}" if block.spring else block.name
        _keep(found, RuleMargin(rule, value, block.unit, value / block.scale))
    linear = problem.linear_rows
    if linear is not None and len(linear):
        matrix, offset = problem.linear_matrix()
        values = matrix @ result.x + offset  # [m]
        for label, value in zip(linear.labels, values.tolist()):
            _keep(found, RuleMargin(_POSE.sub("", str(label)), value, "m", value / linear.scale, True))
    return sorted(found.values(), key=lambda margin: margin.scaled)


def at_bounds(
    result: EvaluatedDesign, tolerance: float = BOUND_TOLERANCE
) -> Iterator[tuple[str, str, str, float, float]]:
    """``(name, unit, side, bound, value)`` of each design variable at (within ``tolerance`` of its range of) its
    ``"upper"`` or ``"lower"`` bound; variables whose bounds are equal are not variables and are skipped."""
    variables = result.problem.variables
    for name, unit, lower, upper, value in zip(
        variables.names, variables.units, variables.lower, variables.upper, result.x.tolist()
    ):
        width = upper - lower
        if not width > 0:
            continue
        if value >= upper - tolerance * width:
            yield name, unit, "upper", upper, value
        elif value <= lower + tolerance * width:
            yield name, unit, "lower", lower, value


def bound_rules(result: EvaluatedDesign, tolerance: float = BOUND_TOLERANCE) -> list[RuleMargin]:
    """The design variables at (within ``tolerance`` of their range of) a bound, as rules of margin 0."""
    return [
        RuleMargin(f"{name} at its {side} bound", 0.0, unit, 0.0)
        for name, unit, side, _, _ in at_bounds(result, tolerance)
    ]


def binding_rules(result: EvaluatedDesign, limit: int = 6) -> list[RuleMargin]:
    """Up to ``limit`` rules that bind at ``result``: the active rows (scaled margin ≤ :data:`ACTIVE`),
    smallest margin first, then the variables at a bound; when none binds, the rule of smallest margin."""
    margins = rule_margins(result)
    active = [margin for margin in margins if margin.scaled <= ACTIVE]
    chosen = (active + bound_rules(result))[:limit]
    return chosen or margins[:1]


def _keep(found: dict[str, RuleMargin], margin: RuleMargin) -> None:
    """Keep the smaller scaled margin of a rule seen twice (rows of one rule at several poses or ends)."""
    known = found.get(margin.rule)
    if known is None or margin.scaled < known.scaled:
        found[margin.rule] = margin
