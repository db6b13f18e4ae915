"""The standard a spring wire is bought to, its grade, and the tolerance on its diameter.

An order for a spring names the wire's standard and grade, and the wire diameter ``d`` with the
tolerance of that standard (DIN 2099-1/-2 ask for both). The standard follows from the material's
label (:data:`~springbalance.springs.materials.MATERIALS`); the tolerance from its table:

- **ASTM A228/A228M** (music wire), permissible variations in diameter, ± (inch, converted to m):
  0.004-0.010 in ±0.0002; over 0.010-0.028 ±0.0003; over 0.028-0.063 ±0.0004; over 0.063-0.080
  ±0.0005; over 0.080-0.250 ±0.001 (ASTM A228/A228M, table of permissible variations in wire
  diameter, as reproduced in The InterWire Group's A228 music wire data sheet).
- **EN 10270-1** (patented cold-drawn unalloyed spring wire, grades SL, SM, SH, DM, DH), ± [mm] for
  ``lower < d ≤ upper``: 0.05-0.09 ±0.003; -0.16 ±0.004; -0.25 ±0.005; -0.63 ±0.008; -0.75 ±0.010;
  -1.00 ±0.015; -1.70 ±0.020; -2.60 ±0.025; -4.00 ±0.030; -5.30 ±0.035; -7.00 ±0.040; -9.00 ±0.045;
  -10.0 ±0.050; -11.0 ±0.070; -14.0 ±0.080; -18.0 ±0.090; -20.0 ±0.100 (EN 10270-1:2011, table of
  diameter tolerances, as listed in the SpringONE project's WIRETOL.csv).

Other wires (ASTM A313 stainless, ASTM A401 chrome-silicon) have no table here: :func:`wire_tolerance`
then says so, and the order asks the maker for the standard's tolerance instead of inventing one.
"""

from __future__ import annotations

import dataclasses

from springbalance.springs.helical_formulas import MM
from springbalance.springs.materials import Material

INCH = 0.0254  # [m]


@dataclasses.dataclass(frozen=True)
class WireStandard:
    """A wire standard: its name, and its tolerance table as ``(upper d [m], ± [m])`` rows, each for
    ``previous upper < d ≤ upper``, from ``lowest`` [m] on (empty when not listed), and the source."""

    name: str
    rows: tuple[tuple[float, float], ...] = ()
    lowest: float = 0.0
    source: str = ""


ASTM_A228 = WireStandard(
    "ASTM A228/A228M",
    tuple(
        (upper * INCH, plus_minus * INCH)
        for upper, plus_minus in ((0.010, 0.0002), (0.028, 0.0003), (0.063, 0.0004), (0.080, 0.0005), (0.250, 0.001))
    ),
    0.0,  # the table starts at 0.004 in; thinner music wire is held to its first row
    "ASTM A228/A228M, permissible variations in wire diameter",
)
EN_10270_1 = WireStandard(
    "EN 10270-1",
    tuple(
        (upper * MM, plus_minus * MM)
        for upper, plus_minus in (
            (0.09, 0.003),
            (0.16, 0.004),
            (0.25, 0.005),
            (0.63, 0.008),
            (0.75, 0.010),
            (1.00, 0.015),
            (1.70, 0.020),
            (2.60, 0.025),
            (4.00, 0.030),
            (5.30, 0.035),
            (7.00, 0.040),
            (9.00, 0.045),
            (10.0, 0.050),
            (11.0, 0.070),
            (14.0, 0.080),
            (18.0, 0.090),
            (20.0, 0.100),
        )
    ),
    0.05 * MM,
    "EN 10270-1:2011, tolerances on the wire diameter",
)
ASTM_A313 = WireStandard("ASTM A313/A313M")
ASTM_A401 = WireStandard("ASTM A401/A401M")
#: a standard named in a material's label → the standard
STANDARDS = {standard.name.split("/")[0]: standard for standard in (ASTM_A228, EN_10270_1, ASTM_A313, ASTM_A401)}
#: the grades of EN 10270-1 (static S*, dynamic D*; low, medium, high strength)
EN_10270_1_GRADES = ("SL", "SM", "SH", "DM", "DH")


def wire_standard(material: Material) -> WireStandard | None:
    """The standard named in ``material``'s label (e.g. "music wire (ASTM A228)"), or None."""
    for key, standard in STANDARDS.items():
        if key in material.label:
            return standard
    return None


def wire_grade(material: Material) -> str:
    """The wire's grade as an order names it: the EN 10270-1 grade (SH, DH, ...) when the material's name
    or label gives one, else the material's label (e.g. "music wire (ASTM A228)")."""
    words = material.label.replace("(", " ").replace(")", " ").replace(",", " ").split()
    words += material.name.upper().replace("-", "_").split("_")
    for grade in EN_10270_1_GRADES:
        if grade in words:
            return grade
    return material.label


def wire_tolerance(material: Material, wire_diameter: float) -> tuple[float | None, str]:
    """The ± tolerance [m] on the diameter ``wire_diameter`` [m] of ``material``'s wire, and its source;
    ``(None, why)`` when no table here covers it."""
    standard = wire_standard(material)
    if standard is None:
        return None, f"no wire standard is known for {material.label}; ask the maker for its tolerance"
    if not standard.rows:
        return None, f"the {standard.name} tolerance table is not included in springbalance; the standard's applies"
    lower = standard.lowest
    if wire_diameter < lower * (1 - 1e-9):
        return None, f"{wire_diameter / MM:g} mm is below the {standard.name} table ({lower / MM:g} mm and up)"
    for upper, plus_minus in standard.rows:
        if wire_diameter <= upper * (1 + 1e-9):
            return plus_minus, standard.source
    return (
        None,
        f"{wire_diameter / MM:g} mm is above the {standard.name} table (up to {standard.rows[-1][0] / MM:g} mm)",
    )
