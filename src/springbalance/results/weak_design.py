"""The ``weak_design`` warning: the springs remove less than half of what their ideal twin removes.

The twin (:mod:`springbalance.design.twin`) is the same problem without the rules that make the springs
real parts (coils' stress, index and envelope rules; clearance and mounting rows). With ``J`` the
optimised objective over the workspace, ``J₀`` its value without springs (gravity only) and ``J_t`` the
twin's, the design removes the fraction ``(J₀ − J)/J₀`` and the twin ``(J₀ − J_t)/J₀``; the design is
weak when

.. math:: \\frac{J_0 - J}{J_0} < \\text{WEAK_FRACTION} \\cdot \\frac{J_0 - J_t}{J_0}, \\qquad \\text{WEAK_FRACTION} = 0.5 .

The warning names the rules that bind at the design (:func:`springbalance.results.rules.binding_rules`):
they are what the balance was given up for. A design without a twin (ideal springs, no clearance, no
mounting, no stock parts) is never weak by this test.
"""

from __future__ import annotations

import math

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.results.flag import Flag
from springbalance.results.rules import binding_rules

#: a design is weak when it removes less than this fraction of what its twin removes
WEAK_FRACTION = 0.5


def _fraction(before: float, after: float) -> float:
    """The fraction [1] of ``before`` removed (NaN when there was nothing to remove)."""
    return (before - after) / before if before > 0 and math.isfinite(before) else math.nan


def weak_design_flags(result: EvaluatedDesign) -> list[Flag]:
    """``weak_design`` when ``result`` removes less than :data:`WEAK_FRACTION` of its twin's share of the
    objective (see the module), naming the binding rules and the per-joint RMS reductions [%]."""
    twin = result.twin
    if twin is None:
        return []
    metrics = result.metrics()
    name = metrics["optimised"]
    row = metrics["objectives"][name]
    design = _fraction(row["before"], row["after"])
    ideal = _fraction(twin.objective_before, twin.objective)
    if not (ideal > 0 and math.isfinite(design)) or design >= WEAK_FRACTION * ideal:
        return []
    joints = {joint["joint"]: joint["rms_reduction_percent"] for joint in metrics["joints"]}
    per_joint = ", ".join(
        f"{joint} {joints.get(joint, math.nan):.1f} % (twin {percent:.1f} %)" for joint, percent in twin.joints.items()
    )
    binding = binding_rules(result)
    rules = ", ".join(margin.rule for margin in binding)
    message = (
        f"the springs remove {100 * design:.1f} % of the {name} objective ({row['before']:.4g} → "
        f"{row['after']:.4g} {row['unit']}), less than half of the {100 * ideal:.1f} % their ideal twin removes "
        f"({twin.source}: {twin.objective:.4g} {row['unit']})"
        + (f"; RMS torque reduction per joint: {per_joint}" if per_joint else "")
        + (f"; the rules that bind: {rules}" if rules else "")
    )
    hint = (
        f"relax what binds ({binding[0].rule}): a larger envelope, a stronger material, wider bounds or a smaller "
        "margin, or add springs"
        if binding
        else "relax the coils' bounds and envelope or the clearance, or add springs"
    )
    return [Flag("weak_design", "design", message, hint)]
