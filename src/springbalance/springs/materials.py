r"""Spring wires: shear modulus, density, tensile strength and allowable stresses (Shigley, chapter 10).

The wire's minimum tensile strength follows a power law ``S_ut = A / d^m`` (Eq. 10-14 and
Table 10-4), and the allowable static shear stress is a fraction of it:

- Table 10-5: shear modulus ``G``;
- Table 10-6: allowable static torsional stress of compression springs (before set
  removal): 45 % of ``S_ut`` for music wire and cold-drawn carbon steel, 50 % for hardened
  and tempered carbon and low-alloy steels (chrome-silicon), 35 % for austenitic stainless;
- Table 10-7: allowable static stress in the body of extension springs: 45 % (carbon and
  low-alloy steels), 35 % (austenitic stainless), and in their hooks;
- Table A-5: unit weight of carbon steel 0.282 lbf/in³ (7800 kg/m³), stainless 18-8
  0.280 lbf/in³ (7750 kg/m³).

European wire, EN 10270-1 grades SH and DH (patented cold-drawn unalloyed spring steel): the
standard's minimum tensile strength fitted by two power laws (0.2–1 mm: A = 2213 MPa·mm^m,
m = 0.146; 1–10 mm: A = 2218 MPa·mm^m, m = 0.200), never above the table (0 to −2.7 %);
G = 81.5 GPa (EN 13906-1), ρ = 7850 kg/m³. docs/model.md §3.8.1 gives the sources.

Every quantity is in SI units (m, N, Pa, kg).
"""

from __future__ import annotations

import dataclasses
from typing import Any

from springbalance.errors import InputError
from springbalance.springs.helical_formulas import MM, MPA, select

#: Preferred wire diameters [m] (the usual metric series of spring-wire tables).
PREFERRED_WIRE_DIAMETERS = tuple(
    MM * d
    for d in (
        0.10,
        0.12,
        0.16,
        0.20,
        0.25,
        0.30,
        0.35,
        0.40,
        0.45,
        0.50,
        0.55,
        0.60,
        0.65,
        0.70,
        0.80,
        0.90,
        1.0,
        1.1,
        1.2,
        1.4,
        1.6,
        1.8,
        2.0,
        2.2,
        2.5,
        2.8,
        3.0,
        3.5,
        4.0,
        4.5,
        5.0,
        5.5,
        6.0,
        6.5,
        7.0,
        8.0,
        9.0,
        10.0,
        11.0,
        12.0,
        13.0,
        14.0,
        15.0,
        16.0,
    )
)

#: the kinds of helical spring
KINDS = ("extension", "compression")


@dataclasses.dataclass(frozen=True)
class StrengthRange:
    """``S_ut = A / d^m`` on ``lower ≤ d ≤ upper``: A [MPa·mm^m], d in mm (Shigley Table 10-4)."""

    lower: float  # [m]
    upper: float  # [m]
    coefficient: float  # A [MPa·mm^m]
    exponent: float  # m


@dataclasses.dataclass(frozen=True)
class Material:
    """A spring wire: shear modulus ``G`` [Pa], density ``rho`` [kg/m³], tensile strength law,
    and the allowable static shear stress as a fraction of ``S_ut`` per spring kind."""

    name: str
    label: str
    shear_modulus: float
    density: float
    strength: tuple[StrengthRange, ...]
    allowable_fraction: dict  # kind ("extension", "compression") -> fraction of S_ut
    #: extension spring ends (Shigley Table 10-7): bending at the hook and torsion at its side bend
    hook_fraction: dict = dataclasses.field(default_factory=lambda: {"bending": 0.75, "torsion": 0.40})

    @property
    def diameter_range(self) -> tuple[float, float]:
        """Smallest and largest wire diameter [m] the strength table covers."""
        return self.strength[0].lower, self.strength[-1].upper

    def tensile_strength(self, wire_diameter: Any) -> Any:
        """Minimum tensile strength ``S_ut = A / d^m`` [Pa] (numbers, arrays or CasADi expressions)."""
        return self.strength_power(wire_diameter, 0.0)

    def strength_power(self, wire_diameter: Any, power: float) -> Any:
        """``S_ut(d) · d^power`` [Pa·m^power], written ``A d^(power - m)`` so that it is finite at
        ``d = 0`` when ``power > m``. The range of ``d`` picks the row of Table 10-4."""
        value = None
        for piece in reversed(self.strength):
            coefficient = piece.coefficient * MPA * MM**piece.exponent  # A [Pa·m^m]
            strength = coefficient * wire_diameter ** (power - piece.exponent)
            value = strength if value is None else select(wire_diameter <= piece.upper, strength, value)
        return value

    def hook_allowable_stress(self, wire_diameter: Any, mode: str) -> Any:
        """Allowable static stress [Pa] in an extension spring's hook: ``mode`` "bending" (section A)
        or "torsion" (section B), Shigley Table 10-7."""
        return self.hook_fraction[mode] * self.tensile_strength(wire_diameter)

    def allowable_stress(self, wire_diameter: Any, kind: str) -> Any:
        """Allowable static shear stress [Pa] of a spring of ``kind`` (Shigley Tables 10-6, 10-7)."""
        return self.allowable_fraction[spring_kind(kind)] * self.tensile_strength(wire_diameter)


#: Common spring wires. Sources: Shigley Tables 10-4 (A, m), 10-5 (G), 10-6/10-7 (allowable
#: fraction of S_ut, static, before set removal), A-5 (density from unit weight).
MATERIALS: dict[str, Material] = {
    material.name: material
    for material in (
        # ASTM A228, d = 0.10–6.5 mm, A = 2211 MPa·mm^m, m = 0.145; G = 81.0 GPa (Table 10-5
        # gives 80.0–82.7 GPa over the sizes; 81.0 GPa for 1.6–3.2 mm).
        Material(
            "music_wire",
            "music wire (ASTM A228)",
            81.0e9,
            7800.0,
            (StrengthRange(0.10 * MM, 6.5 * MM, 2211.0, 0.145),),
            {"compression": 0.45, "extension": 0.45},
        ),
        # ASTM A313 (302 stainless), three diameter ranges in Table 10-4; G = 69.0 GPa.
        Material(
            "stainless_302",
            "stainless steel 302 (ASTM A313)",
            69.0e9,
            7750.0,
            (
                StrengthRange(0.3 * MM, 2.5 * MM, 1867.0, 0.146),
                StrengthRange(2.5 * MM, 5.0 * MM, 2065.0, 0.263),
                StrengthRange(5.0 * MM, 10.0 * MM, 2911.0, 0.478),
            ),
            {"compression": 0.35, "extension": 0.35},
            {"bending": 0.55, "torsion": 0.30},
        ),
        # ASTM A401, d = 1.6–9.5 mm, A = 1974 MPa·mm^m, m = 0.108; G = 77.2 GPa; hardened and
        # tempered low-alloy steel: 50 % (compression), 45 % (extension body).
        Material(
            "chrome_silicon",
            "chrome-silicon (ASTM A401)",
            77.2e9,
            7800.0,
            (StrengthRange(1.6 * MM, 9.5 * MM, 1974.0, 0.108),),
            {"compression": 0.50, "extension": 0.45},
        ),
        *(
            # EN 10270-1 patented cold-drawn unalloyed spring steel wire, grades SH (static duty)
            # and DH (dynamic duty): the same minimum tensile strength, DH also below 0.30 mm.
            # S_ut: a conservative two-piece power law fitted to Rm,min (docs/model.md §3.8.1);
            # G = 81.5 GPa and ρ = 7850 kg/m³ (EN 10270-1 / EN 13906-1 reference values);
            # allowable fractions of cold-drawn carbon steel (Shigley Tables 10-6, 10-7).
            Material(
                f"en10270_1_{grade.lower()}",
                f"patented cold-drawn spring steel EN 10270-1 {grade}",
                81.5e9,
                7850.0,
                (
                    StrengthRange(thinnest * MM, 1.0 * MM, 2213.0, 0.146),
                    StrengthRange(1.0 * MM, 10.0 * MM, 2218.0, 0.200),
                ),
                {"compression": 0.45, "extension": 0.45},
            )
            for grade, thinnest in (("SH", 0.30), ("DH", 0.20))
        ),
    )
}


def material_named(name: str | Material) -> Material:
    """The material called ``name`` (or ``name`` itself when it is a :class:`Material`)."""
    if isinstance(name, Material):
        return name
    if name not in MATERIALS:
        raise InputError(f"unknown spring material {name!r}; valid: {', '.join(MATERIALS)}")
    return MATERIALS[name]


def spring_kind(kind: str) -> str:
    """``kind`` when it is a kind of helical spring (:data:`KINDS`); InputError otherwise."""
    if kind not in KINDS:
        raise InputError(f"helical spring kind must be one of {', '.join(KINDS)}, got {kind!r}")
    return kind
