"""The text of the command line: its name, the one-line errors and warnings, tables, the message of an
interrupted design and the tables of ``springbalance inspect``."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any, TextIO

from springbalance.errors import Interrupted

PROG = "springbalance"

#: finished starts listed by name when a design is interrupted
MAX_STARTS_SHOWN = 8


def print_error(error: object) -> None:
    """``springbalance: error: <message>`` on one line on stderr (the message's whitespace collapsed)."""
    message = " ".join(str(error).split()) or type(error).__name__
    print(f"{PROG}: error: {message}", file=sys.stderr)


def print_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: TextIO | None = None,
    line: str | None = None,
) -> None:
    """A :func:`warnings.showwarning` that prints ``springbalance: warning: <message>`` on one line on stderr."""
    print(f"{PROG}: warning: {' '.join(str(message).split())}", file=sys.stderr)


def interrupted_message(stop: Interrupted, out: Path, partial: bool) -> str:
    """The line printed when Ctrl-C stops ``design``: which starts had finished (their objectives), the best
    feasible one, and whether the best design so far was saved at ``out`` (``--partial`` and a feasible start)."""
    shown = [
        f"{record.index} ({record.objective:.4g}{'' if record.feasible else ', infeasible'})"
        for record in stop.starts[:MAX_STARTS_SHOWN]
    ]
    more = len(stop.starts) - len(shown)
    finished = ", ".join(shown) + (f" and {more} more" if more > 0 else "")
    feasible = [record for record in stop.starts if record.feasible]
    if feasible:
        best = min(feasible, key=lambda record: record.objective)
        finished += f"; best objective {best.objective:.6g} (start {best.index})"
    if partial and stop.best_x is not None:
        saved = f"; the best design so far is saved to {out}"
    elif partial:
        saved = "; no start had finished with a feasible design, so nothing is saved"
    else:
        saved = f"; nothing is saved ({out} is unchanged; --partial saves the best design so far)"
    return f"{PROG}: {stop}{': starts ' + finished if finished else ''}{saved}"


def table(header: list[str], rows: list[list[str]], right: tuple[int, ...] = ()) -> list[str]:
    """Lines of a table indented by two spaces, columns padded to their widest cell (the columns of ``right``
    aligned right)."""
    widths = [max(len(str(row[column])) for row in [header, *rows]) for column in range(len(header))]
    lines = []
    for row in [header, *rows]:
        cells = [
            f"{str(cell):>{width}s}" if column in right else f"{str(cell):<{width}s}"
            for column, (cell, width) in enumerate(zip(row, widths))
        ]
        lines.append(("  " + "  ".join(cells)).rstrip())
    return lines


def number(value: float, digits: int = 6) -> str:
    """``value`` with ``digits`` significant digits, without a negative zero."""
    return f"{value + 0.0:.{digits}g}"


def mechanism_summary(summary: dict[str, Any]) -> str:
    """The text tables of ``springbalance inspect`` for a :meth:`Mechanism.summary
    <springbalance.model.mechanism.Mechanism.summary>` record: a header (source, degrees of freedom, masses
    [kg], gravity [m/s²], ground bodies), the bodies (mass [kg], centre of mass in the body frame [m]) and
    the joints (axis in the joint frame, limits in rad and degrees or in m, mimic coupling)."""
    return "\n".join(_header_lines(summary) + _body_lines(summary["bodies"]) + _joint_lines(summary["joints"]))


def _header_lines(summary: dict[str, Any]) -> list[str]:
    """Name and source, degrees of freedom, masses, gravity and ground of a summary."""
    source = summary["source"]
    where = {
        "robot": f"example-robot-data robot {source.get('robot')!r}, {source.get('path')}",
        "urdf": f"URDF {source.get('path')}",
    }.get(source.get("kind"), source.get("kind"))
    if source.get("mimic"):
        where += ", mimic joints coupled"
    dof_names = [joint["name"] for joint in summary["joints"] if joint["dof"]]
    return [
        f"{summary['name']} ({where})",
        f"  {summary['dofs']} degree{'' if summary['dofs'] == 1 else 's'} of freedom: {', '.join(dof_names) or '—'}",
        f"  total mass {number(summary['total_mass'])} kg, of which {number(summary['moving_mass'])} kg moves",
        f"  gravity ({', '.join(number(value) for value in summary['gravity'])}) m/s²",
        f"  ground (cannot move): {', '.join(summary['ground'])}",
        "",
    ]


def _body_lines(bodies: list[dict[str, Any]]) -> list[str]:
    """The table of the bodies: mass [kg], centre of mass in the body frame [m], parent joint, moving joint."""
    rows = [
        [
            body["name"],
            number(body["mass"]),
            "(" + ", ".join(number(value) for value in body["com"]) + ")",
            body["parent_joint"] or "—",
            "ground" if body["ground"] else body["moved_by"],
        ]
        for body in bodies
    ]
    return [
        "bodies (centre of mass in the body frame)",
        *table(["body", "mass [kg]", "centre of mass [m]", "parent joint", "moved by"], rows, right=(1,)),
    ]


def _joint_lines(joints: list[dict[str, Any]]) -> list[str]:
    """The table of the joints: type, parent → child, axis in the joint frame, limits."""
    rows = []
    for joint in joints:
        axis = "—" if joint["axis"] is None else "(" + ", ".join(number(value) for value in joint["axis"]) + ")"
        rows.append([joint["name"], joint["type"], f"{joint['parent']} → {joint['child']}", axis, _limits(joint)])
    return ["", "joints (axis in the joint frame)", *table(["joint", "type", "parent → child", "axis", "limits"], rows)]


def _limits(joint: dict[str, Any]) -> str:
    """A joint's range [rad, also in degrees, or m], or its mimic coupling ``multiplier × joint + offset``."""
    if joint["mimic"] is not None:
        mimic = joint["mimic"]
        return f"mimic: {number(mimic['multiplier'])} × {mimic['joint']} + {number(mimic['offset'])}"
    if joint["lower"] is None:
        return "—"
    limits = f"{number(joint['lower'], 5)} … {number(joint['upper'], 5)} {joint['unit']}"
    if joint["unit"] == "rad":
        lower, upper = (round(math.degrees(joint[end]), 1) for end in ("lower", "upper"))
        limits += f" ({number(lower)}° … {number(upper)}°)"
    if joint["type"] == "continuous":
        limits += ", no stops"
    return limits
