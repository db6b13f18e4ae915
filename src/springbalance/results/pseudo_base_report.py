"""The pseudo-base section of the reports (text, ``report.html`` and ``design.json``): each pseudo-base's mass and
the gravity torque that mass adds before balancing (:mod:`springbalance.model.pseudo_base_weight`, docs/model.md §1.1).

Per joint, the peak over the workspace of the pseudo-bases' combined torque [N·m or N], and that peak as a share
of the peak of the whole arm's gravity torque (pseudo-bases included) on that joint.
"""

from __future__ import annotations

import html
from typing import Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.model.pseudo_base_weight import pseudo_base_torques


def pseudo_base_record(result: EvaluatedDesign) -> dict[str, Any]:
    """``{"pseudo_bases": …}`` for ``design.json`` (empty without pseudo-bases): ``bases`` (per pseudo-base
    ``joint``, ``body``, ``mass`` [kg], ``com`` [m], ``peak_torque`` per joint), ``total_mass`` [kg],
    ``peak_torque`` per joint (all of them together) and ``share_of_gravity_peak`` per joint (a fraction)."""
    mechanism = result.problem.mechanism
    if not mechanism.pseudo_bases:
        return {}
    kinematics = result.problem.base_workspace.kinematics()
    torques = pseudo_base_torques(kinematics)
    names = mechanism.joint_names
    gravity_peak = np.max(np.abs(kinematics.gravity_torque), axis=0, initial=0.0)
    bases = []
    for base in mechanism.pseudo_bases:
        peak = np.max(np.abs(torques[base.body]), axis=0, initial=0.0)
        bases.append({**base.to_dict(), "body": base.body, "peak_torque": dict(zip(names, map(float, peak)))})
    total = np.max(np.abs(sum(torques.values())), axis=0, initial=0.0)
    share = [float(p / g) if g > 0 else 0.0 for p, g in zip(total, gravity_peak)]
    return {
        "pseudo_bases": {
            "bases": bases,
            "total_mass": float(sum(base.mass for base in mechanism.pseudo_bases)),
            "peak_torque": dict(zip(names, map(float, total))),
            "share_of_gravity_peak": dict(zip(names, share)),
        }
    }


def pseudo_base_lines(result: EvaluatedDesign) -> list[str]:
    """The "Pseudo-bases" section of the text report (nothing without pseudo-bases)."""
    record = pseudo_base_record(result).get("pseudo_bases")
    if record is None:
        return []
    lines = ["", f"Pseudo-bases (world-oriented anchors, docs/model.md §1.1): {record['total_mass']:.4g} kg in all"]
    for base in record["bases"]:
        com = ", ".join(f"{v:.4g}" for v in base["com"])
        keeps = ", keeps only the vertical" if base.get("keep") == "vertical" else ""
        lines.append(
            f"  {base['body']:<16} at joint {base['joint']}: {base['mass']:.4g} kg, centre of mass ({com}) m{keeps}"
        )
    units = {joint.name: joint.torque_unit for joint in result.problem.mechanism.joints}
    largest = max(record["peak_torque"].values(), default=0.0)
    added = ", ".join(
        f"{joint} {peak:.4g} {units[joint]} ({100 * record['share_of_gravity_peak'][joint]:.3g} %)"
        for joint, peak in record["peak_torque"].items()
        if peak > 1e-12 * largest  # round-off on joints the pseudo-bases do not load
    )
    lines.append(f"  their weight adds, before balancing (peak; share of the gravity peak): {added or 'nothing'}")
    return lines


def pseudo_base_html(result: EvaluatedDesign) -> list[str]:
    """The "Pseudo-bases" section of ``report.html`` (nothing without pseudo-bases): per pseudo-base its body, joint,
    what it keeps, mass [kg], centre of mass [m] and the peak torque its weight adds per joint before balancing;
    then all of them together, with each peak's share of the arm's gravity peak (the text report's facts)."""
    record = pseudo_base_record(result).get("pseudo_bases")
    if record is None:
        return []
    e = html.escape
    units = {joint.name: joint.torque_unit for joint in result.problem.mechanism.joints}
    largest = max(record["peak_torque"].values(), default=0.0)

    def added(peaks: dict[str, float], shares: dict[str, float] | None = None) -> str:
        cells = [
            f"{joint} {peak:.4g} {units[joint]}" + (f" ({100 * shares[joint]:.3g} %)" if shares else "")
            for joint, peak in peaks.items()
            if peak > 1e-12 * largest  # round-off on joints the pseudo-bases do not load
        ]
        return e(", ".join(cells) or "nothing")

    parts = [
        '<h2 id="pseudo-bases">Pseudo-bases</h2>',
        f"<p>Auxiliary bodies at joint origins that keep the world's orientation (or only its vertical), realised by "
        f"parallelograms (docs/model.md §1.1): {record['total_mass']:.4g} kg in all. Their weight adds, before "
        f"balancing (peak; share of the gravity peak): {added(record['peak_torque'], record['share_of_gravity_peak'])}"
        ".</p>",
        "<table><tr><th class=l>pseudo-base</th><th class=l>joint</th><th class=l>keeps</th><th>mass [kg]</th>"
        "<th>centre of mass [m]</th><th class=l>its weight adds (peak)</th></tr>",
    ]
    for base in record["bases"]:
        com = ", ".join(f"{v:.4g}" for v in base["com"])
        parts.append(
            f"<tr><td class=l>{e(base['body'])}</td><td class=l>{e(base['joint'])}</td>"
            f"<td class=l>{e(base.get('keep', 'orientation'))}</td><td>{base['mass']:.4g}</td><td>({e(com)})</td>"
            f"<td class=l>{added(base['peak_torque'])}</td></tr>"
        )
    parts.append("</table>")
    return parts
