"""``short_life``: a coil that states no ``duty`` and would not live the default one.

A coil with a ``duty`` record is designed for it: fatigue is a rule at every sample, and a location below its
safety factor makes the coil unbuildable. A coil without one is still judged at the default duty
(:class:`springbalance.springs.fatigue.Duty`: 10⁶ cycles, n_f ≥ 1.2, Gerber; docs/model.md §3.8.2), and a
location that falls short is this warning: the design holds statically, but the spring may break in service.
"""

from __future__ import annotations

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.results.flag import Flag


def short_life_flags(result: EvaluatedDesign) -> list[Flag]:
    """One ``short_life`` flag per coil without a stated duty whose weakest location misses the default ``n_f``."""
    found = []
    for record in result.springs:
        sheet = record.get("helical")
        if not isinstance(sheet, dict) or not isinstance(sheet.get("fatigue"), dict):
            continue
        duty = sheet.get("duty") or {}
        if duty.get("stated", True):
            continue
        margins = [(key, m) for key, m in sheet["fatigue"].items() if isinstance(m, dict)]
        short = [
            (key, m) for key, m in margins if m["safety_factor"] is not None and m["safety_factor"] < m["required"]
        ]
        if not short:
            continue
        location, margin = min(short, key=lambda item: item[1]["safety_factor"])
        found.append(
            Flag(
                "short_life",
                record["name"],
                f"spring {record['name']!r} states no duty; at the default one ({duty['cycles']:.0e} cycles, "
                f"n_f ≥ {margin['required']:g}) its {location.replace('_', ' ')} reaches n_f = "
                f"{margin['safety_factor']:.2f} and lives {margin['life_text']}",
                f"give the spring a duty (e.g. duty: {{cycles: {duty['cycles']:.0e}}}) so that fatigue is designed "
                "for at every sample (docs/guides/coils-and-stock.md)",
            )
        )
    return found
