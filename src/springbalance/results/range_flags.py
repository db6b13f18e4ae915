"""Warnings about values outside their usual range: a workspace beyond the joints' limits
(``beyond_joint_limits``), a coil's wire off the preferred series (``off_series_wire``).

- ``beyond_joint_limits``: a joint value of the workspace (the poses the design balances) lies beyond
  the joint's position limits in the URDF (``<limit lower upper>``), by more than
  :data:`LIMIT_TOLERANCE` [rad or m]. Continuous joints, and joints whose model gives no finite limits,
  have none. The arm cannot take such poses, so the design is balanced for motion it will not make (and
  may be the worse where it will). :func:`beyond_joint_limits` checks a mechanism's joint values before
  a solve (the command line warns early).
- ``off_series_wire``: a helical coil (not a stock part) whose wire diameter is not one of the standard sizes
  (the design's ``solve.wire_sizes`` when given, else the preferred series
  :data:`~springbalance.springs.sizing.PREFERRED_WIRE_DIAMETERS`, within a relative 1e-6): standard
  wire was turned off, or the rounding left it continuous (``wire_rounding.unrounded`` says why).
"""

from __future__ import annotations

import math

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.model.mechanism import Mechanism
from springbalance.results.flag import Flag
from springbalance.springs.sizing import PREFERRED_WIRE_DIAMETERS

#: joint values beyond a limit by at most this much [rad or m] are round-off (a range given in degrees)
LIMIT_TOLERANCE = 1e-9


def position_limits(mechanism: Mechanism) -> dict[str, tuple[float, float]]:
    """Joint name → ``(lower, upper)`` [rad or m] of every joint with finite position limits in the model
    (revolute and prismatic joints of a URDF; not continuous joints)."""
    model = mechanism.model
    limits = {}
    for joint in mechanism.joints:
        if joint.kind == "continuous":
            continue
        lower, upper = float(model.lowerPositionLimit[joint.index_q]), float(model.upperPositionLimit[joint.index_q])
        if math.isfinite(lower) and math.isfinite(upper) and lower < upper:
            limits[joint.name] = (lower, upper)
    return limits


def beyond_joint_limits(mechanism: Mechanism, joint_values: np.ndarray) -> list[Flag]:
    """``beyond_joint_limits``: one warning per joint whose values (N×nv [rad or m]) leave its limits."""
    values = np.asarray(joint_values, dtype=float).reshape(-1, mechanism.nv)
    found = []
    known = position_limits(mechanism)
    for joint in mechanism.joints:
        limits = known.get(joint.name)
        if limits is None or not values.size:
            continue
        lower, upper = limits
        column = values[:, joint.index_v]
        low, high = float(np.min(column)), float(np.max(column))
        if low >= lower - LIMIT_TOLERANCE and high <= upper + LIMIT_TOLERANCE:
            continue
        outside = int(np.sum((column < lower - LIMIT_TOLERANCE) | (column > upper + LIMIT_TOLERANCE)))
        found.append(
            Flag(
                "beyond_joint_limits",
                joint.name,
                f"the workspace takes joint {joint.name} over {_range(low, high, joint.unit)}, beyond its URDF "
                f"limits {_range(lower, upper, joint.unit)} ({outside} of {len(column)} samples outside)",
                f"keep workspace.ranges.{joint.name} within {_range(lower, upper, joint.unit)}, or correct the "
                "URDF's limits if the arm really moves that far",
            )
        )
    return found


def _range(low: float, high: float, unit: str) -> str:
    """``[low, high] unit``, with degrees beside radians."""
    if unit == "rad":
        return f"[{low:.4g}, {high:.4g}] rad ([{math.degrees(low):.1f}°, {math.degrees(high):.1f}°])"
    return f"[{low:.4g}, {high:.4g}] {unit}"


def beyond_joint_limits_flags(result: EvaluatedDesign) -> list[Flag]:
    """``beyond_joint_limits`` of ``result``'s workspace (its poses, before any scenarios are stacked)."""
    problem = result.problem
    return beyond_joint_limits(problem.mechanism, problem.base_workspace.joint_values)


def off_series_wire_flags(result: EvaluatedDesign) -> list[Flag]:
    """``off_series_wire``: helical coils whose wire diameter is not a preferred size (see the module)."""
    unrounded = result.wire_rounding.unrounded if result.wire_rounding is not None else {}
    given = getattr(result, "wire_sizes", None)  # a DesignResult's solve.wire_sizes
    series, named = (given, "one of solve.wire_sizes") if given else (PREFERRED_WIRE_DIAMETERS, "a preferred size")
    found = []
    for record in result.springs:
        if not isinstance(record.get("helical"), dict) or "wire_diameter" not in record:
            continue
        if record.get("part_number") is not None:  # a bought part: its wire is the part's (MS parts: inch sizes)
            continue
        wire = float(record["wire_diameter"])  # [m]
        if any(math.isclose(wire, size, rel_tol=1e-6) for size in series):
            continue
        nearest = min(series, key=lambda size: abs(size - wire))
        reason = unrounded.get(record["name"])
        found.append(
            Flag(
                "off_series_wire",
                record["name"],
                f"spring {record['name']!r} has a wire of {1e3 * wire:.4g} mm, not {named} (nearest "
                f"{1e3 * nearest:.4g} mm)" + (f"; the rounding left it: {reason}" if reason else ""),
                "turn standard_wire on (solve.standard_wire) or fix the wire at a standard size; a spring maker "
                "draws wire in its sizes (give yours as solve.wire_sizes [m]), another one is a special order",
            )
        )
    return found
