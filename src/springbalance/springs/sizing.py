r"""Helical coil springs: materials, textbook relations, and sizing a designed spring.

A helical spring of round wire (diameter ``d``), mean coil diameter ``D``, index
``C = D/d`` and ``n`` active coils, of a wire with shear modulus ``G``:

.. math::
    k = \frac{G d^4}{8 D^3 n},\qquad
    \tau = K_W \frac{8 F D}{\pi d^3},\qquad
    K_W = \frac{4C - 1}{4C - 4} + \frac{0.615}{C},

rate ``k`` [N/m], shear stress ``τ`` [Pa] at the inside of the coil under axial force ``F``
[N], with the Wahl factor ``K_W`` (direct shear plus curvature). The wire's minimum
tensile strength follows a power law ``S_ut = A / d^m``, and the allowable static shear
stress is a fraction of it. References (Shigley's Mechanical Engineering Design, Budynas &
Nisbett, 9th ed. 2011 / 10th ed. 2015, chapter 10):

- Eq. (10-9): rate ``k = d⁴G/(8D³N_a)``; Eq. (10-5): Wahl factor ``K_W``; Eq. (10-6):
  Bergsträsser factor ``K_B = (4C + 2)/(4C − 3)`` (the two differ by less than 1 %);
- Eq. (10-14) and Table 10-4: ``S_ut = A/d^m``; Table 10-5: shear modulus ``G``;
- Table 10-6: allowable static torsional stress of compression springs (before set
  removal): 45 % of ``S_ut`` for music wire and cold-drawn carbon steel, 50 % for hardened
  and tempered carbon and low-alloy steels (chrome-silicon), 35 % for austenitic stainless;
- Table 10-7: allowable static stress in the body of extension springs: 45 % (carbon and
  low-alloy steels), 35 % (austenitic stainless);
- Table 10-1: squared-and-ground compression springs have ``N_t = N_a + 2`` total coils and
  solid length ``L_s = d N_t``; §10-11: an extension spring with machine hooks has body
  length ``L_b = d (N_b + 1)`` and free length ``L_0 = 2(D − d) + L_b``;
- Table A-5: unit weight of carbon steel 0.282 lbf/in³ (7800 kg/m³), stainless 18-8
  0.280 lbf/in³ (7750 kg/m³).

Two uses:

- :func:`size_helical_spring` proposes a wire (a preferred size), a mean coil diameter
  and a number of active coils for a designed ``(k, l0, max length, max force)`` and says
  plainly when no helical spring of the material can do it;
- :class:`Helical` is the spring option behind the optimisation constraints of
  :mod:`springbalance.springs.constraints` that keep a design realisable by a helical spring of a
  chosen index (see :meth:`Helical.fitting_wire`).

Every quantity is in SI units (m, N, Pa, kg).
"""

from __future__ import annotations

import dataclasses
import math
import typing
from typing import Sequence

import casadi as ca
import numpy as np

from springbalance.errors import InputError

MPA = 1e6   # [Pa]
MM = 1e-3   # [m]

#: Preferred wire diameters [m] (the usual metric series of spring-wire tables).
PREFERRED_WIRE_DIAMETERS = tuple(MM * d for d in (
    0.10, 0.12, 0.16, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50, 0.55, 0.60, 0.65, 0.70, 0.80, 0.90,
    1.0, 1.1, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2, 2.5, 2.8, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5, 7.0,
    8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0, 16.0))

KINDS = ("extension", "compression")


# ---------------------------------------------------------------------- textbook relations
def wahl_factor(index):
    r"""Wahl factor :math:`K_W = (4C - 1)/(4C - 4) + 0.615/C` (Shigley Eq. 10-5), dimensionless."""
    return (4 * index - 1) / (4 * index - 4) + 0.615 / index


def bergstrasser_factor(index):
    r"""Bergsträsser factor :math:`K_B = (4C + 2)/(4C - 3)` (Shigley Eq. 10-6), dimensionless."""
    return (4 * index + 2) / (4 * index - 3)


def spring_rate(shear_modulus, wire_diameter, mean_diameter, active_coils):
    r"""Rate :math:`k = G d^4 / (8 D^3 n)` [N/m] (Shigley Eq. 10-9); G [Pa], d and D [m]."""
    return shear_modulus * wire_diameter**4 / (8 * mean_diameter**3 * active_coils)


def shear_stress(force, wire_diameter, mean_diameter, factor=wahl_factor):
    r"""Corrected shear stress :math:`\tau = K \, 8 F D / (\pi d^3)` [Pa] under axial force F [N].

    ``factor`` maps the index ``C = D/d`` to the correction (default the Wahl factor).
    """
    return factor(mean_diameter / wire_diameter) * 8 * force * mean_diameter / (math.pi * wire_diameter**3)


def coil_mass(stiffness, coil_diameter, active_coils, wire_length, shear_modulus, density):
    r"""Mass [kg] of a coil of fixed ``D`` and ``n`` whose wire diameter gives rate ``k``
    (docs/model.md §5): :math:`m_s = \rho \pi L_w \sqrt{D^3 n k / (2 G)}`.

    From :math:`k = G d^4/(8 D^3 n)`, :math:`d^2 = \sqrt{8 D^3 n k / G}` and
    :math:`m_s = \rho L_w \pi d^2 / 4`. Works on numbers and CasADi expressions.
    """
    return density * math.pi * wire_length * (coil_diameter**3 * active_coils * stiffness / (2 * shear_modulus)) ** 0.5


def initial_stress_band(index):
    r"""Preferred range ``(low, high)`` [Pa] of the uncorrected initial stress of a close-wound
    extension spring of index ``C`` (Shigley Eq. 10-40, fitted to the wire makers' chart):

    .. math:: \tau_i = \frac{231}{e^{0.105 C}} \pm 6.9\Bigl(4 - \frac{C - 3}{6.5}\Bigr)\ \mathrm{MPa},

    with :math:`\tau_i = 8 F_i D / (\pi d^3)` for an initial tension ``F_i`` [N]. Works on numbers,
    arrays and CasADi expressions.
    """
    middle = 231.0 * MPA * _exp(-0.105 * index)                      # [Pa]
    half_width = 6.9 * MPA * (4.0 - (index - 3.0) / 6.5)              # [Pa]
    return middle - half_width, middle + half_width


def hook_bending_stress(force, wire_diameter, mean_diameter):
    r"""Bending stress [Pa] at the top of a machine hook (section A, Shigley Eq. 10-34, 10-35), with the
    hook's bend index ``C_1 = 2 r_1/d = D/d`` (the hook as wide as the coil):

    .. math:: \sigma_A = F\Bigl[(K)_A \frac{16 D}{\pi d^3} + \frac{4}{\pi d^2}\Bigr],\qquad
              (K)_A = \frac{4 C_1^2 - C_1 - 1}{4 C_1 (C_1 - 1)} .
    """
    c1 = mean_diameter / wire_diameter
    factor = (4 * c1 * c1 - c1 - 1) / (4 * c1 * (c1 - 1))
    return force * (factor * 16 * mean_diameter / (math.pi * wire_diameter**3) + 4 / (math.pi * wire_diameter**2))


#: bend index ``C_2 = 2 r_2 / d`` of the side bend of a machine hook (section B); Shigley asks for C_2 > 4.
HOOK_SIDE_BEND_INDEX = 4.0


def hook_torsion_stress(force, wire_diameter, mean_diameter, side_bend_index=HOOK_SIDE_BEND_INDEX):
    r"""Torsional stress [Pa] at the side bend of a machine hook (section B, Shigley Eq. 10-36):
    :math:`\tau_B = (K)_B\, 8 F D/(\pi d^3)`, :math:`(K)_B = (4 C_2 - 1)/(4 C_2 - 4)`."""
    factor = (4 * side_bend_index - 1) / (4 * side_bend_index - 4)
    return factor * 8 * force * mean_diameter / (math.pi * wire_diameter**3)


def _exp(value):
    return ca.exp(value) if isinstance(value, (ca.SX, ca.MX, ca.DM)) else np.exp(value)


# ---------------------------------------------------------------------- materials
@dataclasses.dataclass(frozen=True)
class StrengthRange:
    """``S_ut = A / d^m`` on ``lower ≤ d ≤ upper``: A [MPa·mm^m], d in mm (Shigley Table 10-4)."""

    lower: float       # [m]
    upper: float       # [m]
    coefficient: float  # A [MPa·mm^m]
    exponent: float    # m


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

    def tensile_strength(self, wire_diameter):
        """Minimum tensile strength ``S_ut = A / d^m`` [Pa] (numbers, arrays or CasADi expressions)."""
        return self.strength_power(wire_diameter, 0.0)

    def strength_power(self, wire_diameter, power: float):
        """``S_ut(d) · d^power`` [Pa·m^power], written ``A d^(power - m)`` so that it is finite at
        ``d = 0`` when ``power > m``. The range of ``d`` picks the row of Table 10-4."""
        value = None
        for piece in reversed(self.strength):
            coefficient = piece.coefficient * MPA * MM**piece.exponent          # A [Pa·m^m]
            strength = coefficient * wire_diameter ** (power - piece.exponent)
            value = strength if value is None else _select(wire_diameter <= piece.upper, strength, value)
        return value

    def hook_allowable_stress(self, wire_diameter, mode: str):
        """Allowable static stress [Pa] in an extension spring's hook: ``mode`` "bending" (section A)
        or "torsion" (section B), Shigley Table 10-7."""
        return self.hook_fraction[mode] * self.tensile_strength(wire_diameter)

    def allowable_stress(self, wire_diameter, kind: str):
        """Allowable static shear stress [Pa] of a spring of ``kind`` (Shigley Tables 10-6, 10-7)."""
        return self.allowable_fraction[_kind(kind)] * self.tensile_strength(wire_diameter)


def _select(condition, if_true, if_false):
    if isinstance(condition, (ca.SX, ca.MX, ca.DM)) or isinstance(if_true, (ca.SX, ca.MX)):
        return ca.if_else(condition, if_true, if_false)
    return np.where(condition, if_true, if_false)


#: Common spring wires. Sources: Shigley Tables 10-4 (A, m), 10-5 (G), 10-6/10-7 (allowable
#: fraction of S_ut, static, before set removal), A-5 (density from unit weight).
MATERIALS: dict[str, Material] = {
    material.name: material for material in (
        # ASTM A228, d = 0.10–6.5 mm, A = 2211 MPa·mm^m, m = 0.145; G = 81.0 GPa (Table 10-5
        # gives 80.0–82.7 GPa over the sizes; 81.0 GPa for 1.6–3.2 mm).
        Material("music_wire", "music wire (ASTM A228)", 81.0e9, 7800.0,
                 (StrengthRange(0.10 * MM, 6.5 * MM, 2211.0, 0.145),),
                 {"compression": 0.45, "extension": 0.45}),
        # ASTM A313 (302 stainless), three diameter ranges in Table 10-4; G = 69.0 GPa.
        Material("stainless_302", "stainless steel 302 (ASTM A313)", 69.0e9, 7750.0,
                 (StrengthRange(0.3 * MM, 2.5 * MM, 1867.0, 0.146),
                  StrengthRange(2.5 * MM, 5.0 * MM, 2065.0, 0.263),
                  StrengthRange(5.0 * MM, 10.0 * MM, 2911.0, 0.478)),
                 {"compression": 0.35, "extension": 0.35}, {"bending": 0.55, "torsion": 0.30}),
        # ASTM A401, d = 1.6–9.5 mm, A = 1974 MPa·mm^m, m = 0.108; G = 77.2 GPa; hardened and
        # tempered low-alloy steel: 50 % (compression), 45 % (extension body).
        Material("chrome_silicon", "chrome-silicon (ASTM A401)", 77.2e9, 7800.0,
                 (StrengthRange(1.6 * MM, 9.5 * MM, 1974.0, 0.108),),
                 {"compression": 0.50, "extension": 0.45}),
    )
}


def material_named(name) -> Material:
    """The material called ``name`` (or ``name`` itself when it is a :class:`Material`)."""
    if isinstance(name, Material):
        return name
    if name not in MATERIALS:
        raise InputError(f"unknown spring material {name!r}; valid: {', '.join(MATERIALS)}")
    return MATERIALS[name]


def _kind(kind: str) -> str:
    if kind not in KINDS:
        raise InputError(f"helical spring kind must be one of {', '.join(KINDS)}, got {kind!r}")
    return kind


# ---------------------------------------------------------------------- the optimisation option
class Helical:
    r"""Spring option: the design must be realisable as a helical spring of ``material`` with
    spring index ``C = index`` and at least ``min_active_coils`` active coils.

    For a rate ``k`` the coil has ``n = G d / (8 C^3 k)`` active coils, so its length grows
    with the wire diameter ``d``:

    - extension spring (machine hooks, closed body): free length
      :math:`L_0(d) = G d^2/(8 C^3 k) + (2C - 1) d`, which must not exceed the designed free
      length ``l0``;
    - compression spring (squared and ground ends): solid length
      :math:`L_s(d) = G d^2/(8 C^3 k) + 2 d`, which must not exceed the working length ``L``.

    A wire of diameter ``d`` carries at most
    :math:`F_{allow}(d) = \pi f S_{ut}(d) d^2 / (8 K_W(C) C)` [N] (``f``: allowable fraction),
    which grows with ``d``. So a spring exists iff the largest wire that still fits,
    ``d* = min(d_fit, d_max)``, carries the force, has room for ``n_min`` coils and is
    not thinner than the material's smallest wire; :mod:`springbalance.springs.constraints` writes these
    conditions as rows, exactly.
    """

    def __init__(self, material="music_wire", index: float = 8.0, min_active_coils: float = 3.0):
        self.material = material_named(material)
        index, min_active_coils = float(index), float(min_active_coils)
        if not 4.0 <= index <= 15.0:
            raise InputError(f"helical spring index C = D/d must lie in 4–15, got {index}")
        if not min_active_coils >= 1.0:
            raise InputError(f"helical spring min_active_coils must be ≥ 1, got {min_active_coils}")
        self.index, self.min_active_coils = index, min_active_coils

    def coil_length(self, wire_diameter, stiffness, kind: str):
        """Free length (extension, hooks included) or solid length (compression) [m] of the coil
        with wire ``d`` and rate ``k`` (``n = G d / (8 C³ k)`` active coils)."""
        body = self.material.shear_modulus * wire_diameter**2 / (8 * self.index**3 * stiffness)  # d·n [m]
        return body + (2 * self.index - 1 if _kind(kind) == "extension" else 2.0) * wire_diameter

    def fitting_wire(self, room, stiffness, kind: str):
        r"""Largest wire diameter [m] whose coil fits in length ``room`` [m] (root of
        :math:`a d^2 + b d = \mathrm{room}` with :math:`a = G/(8C^3 k)`), written
        :math:`2\,\mathrm{room}\,k / (b k + \sqrt{b^2 k^2 + 4 G\,\mathrm{room}\,k/(8C^3)})` so that it
        stays finite as ``k`` → 0."""
        b = 2 * self.index - 1 if _kind(kind) == "extension" else 2.0
        c = self.material.shear_modulus / (8 * self.index**3)     # G/(8C³) [Pa]
        return 2 * room * stiffness / (b * stiffness + (b * b * stiffness * stiffness + 4 * c * room * stiffness) ** 0.5)

    def allowable_force(self, wire_diameter, kind: str):
        """Largest axial force [N] a wire of diameter ``d`` carries at this index."""
        fraction = self.material.allowable_fraction[_kind(kind)]
        stress_area = self.material.strength_power(wire_diameter, 2.0)    # S_ut d² [N]
        return math.pi * fraction * stress_area / (8 * wahl_factor(self.index) * self.index)

    def coil_wire(self, stiffness):
        """Smallest wire diameter [m] that gives ``min_active_coils`` coils at rate ``k``."""
        return 8 * self.index**3 * stiffness * self.min_active_coils / self.material.shear_modulus

    @property
    def max_stiffness(self) -> float:
        """Largest rate [N/m] with ``min_active_coils`` coils on the material's thickest wire."""
        return self.material.shear_modulus * self.material.diameter_range[1] / (8 * self.index**3 * self.min_active_coils)

    def to_dict(self) -> dict:
        return {"material": self.material.name, "index": self.index, "min_active_coils": self.min_active_coils}

    def __repr__(self) -> str:
        return f"Helical({self.material.name!r}, index={self.index}, min_active_coils={self.min_active_coils})"


#: The type of the ``helical`` option in the config schema: a forward reference to the pydantic
#: record :class:`springbalance.springs.options.HelicalOption`, which the schema resolves (so that
#: the spring laws load without pydantic).
HELICAL_OPTION = typing.ForwardRef("HelicalOption", module="springbalance.springs.options")


def __getattr__(name: str):
    if name == "HelicalOption":  # where it was defined before springbalance.springs.options
        from springbalance.springs.options import HelicalOption

        return HelicalOption
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def helical_from_dict(record, where: str = "helical") -> Helical:
    """``{material?, index?, min_active_coils?}`` → :class:`Helical`."""
    if isinstance(record, Helical):
        return record
    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping {{material, index, min_active_coils}}, got {record!r}")
    unknown = [key for key in record if key not in ("material", "index", "min_active_coils")]
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r}; valid keys: material, index, min_active_coils")
    try:
        return Helical(record.get("material", "music_wire"), _number(record.get("index", 8.0), f"{where}.index"),
                       _number(record.get("min_active_coils", 3.0), f"{where}.min_active_coils"))
    except InputError as error:
        raise InputError(f"{where}: {error}") from None


def _number(value, where):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise InputError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


# ---------------------------------------------------------------------- sizing a designed spring
@dataclasses.dataclass
class HelicalDesign:
    """A proposed helical spring, or the plain reason why none exists.

    Lengths in m, forces in N, stresses in Pa, mass in kg.
    """

    feasible: bool
    kind: str
    material: str
    stiffness: float                 # designed rate [N/m]
    free_length: float               # designed free length l0 [m]
    max_length: float                # longest working length [m]
    min_length: float                # shortest working length [m]
    max_force: float                 # largest |F| [N]
    reasons: list = dataclasses.field(default_factory=list)
    wire_diameter: float = float("nan")
    mean_diameter: float = float("nan")
    index: float = float("nan")
    active_coils: float = float("nan")
    total_coils: float = float("nan")
    solid_length: float = float("nan")   # compression: d N_t; extension: closed body d (n + 1)
    coil_free_length: float = float("nan")  # extension: body + hooks; compression: l0
    wire_length: float = float("nan")
    mass: float = float("nan")
    wahl_factor: float = float("nan")
    stress: float = float("nan")          # at max_force [Pa]
    allowable_stress: float = float("nan")
    tensile_strength: float = float("nan")
    rate: float = float("nan")            # G d⁴/(8 D³ n) of the proposal [N/m]
    notes: list = dataclasses.field(default_factory=list)

    @property
    def utilisation(self) -> float:
        """Stress at max force over allowable stress."""
        return self.stress / self.allowable_stress

    def to_dict(self) -> dict:
        record = dataclasses.asdict(self)
        return {key: (None if isinstance(value, float) and not np.isfinite(value) else value)
                for key, value in record.items()}

    def summary(self) -> str:
        """Two or three lines of plain text."""
        head = f"helical {self.kind} spring, {MATERIALS[self.material].label if self.material in MATERIALS else self.material}"
        if not self.feasible:
            return f"{head}: NOT FEASIBLE — " + "; ".join(self.reasons)
        lines = [f"{head}: wire d {self.wire_diameter * 1e3:.2f} mm, mean coil D {self.mean_diameter * 1e3:.1f} mm "
                 f"(index {self.index:.2f}), {self.active_coils:g} active / {self.total_coils:g} total coils, "
                 f"mass {self.mass:.3g} kg",
                 f"stress at {self.max_force:.4g} N: {self.stress / MPA:.0f} MPa (Wahl {self.wahl_factor:.3f}) of "
                 f"{self.allowable_stress / MPA:.0f} MPa allowable ({100 * self.utilisation:.0f} %), "
                 f"{'solid length' if self.kind == 'compression' else 'coil free length'} "
                 f"{(self.solid_length if self.kind == 'compression' else self.coil_free_length) * 1e3:.1f} mm"]
        lines += self.notes
        return "\n".join(lines)


def size_helical_spring(stiffness: float, free_length: float, max_length: float, max_force: float,
                        material="music_wire", kind: str = "extension", min_length: float | None = None,
                        index_range: Sequence[float] = (4.0, 15.0), min_active_coils: float = 3.0,
                        wire_diameters: Sequence[float] = PREFERRED_WIRE_DIAMETERS,
                        coil_step: float = 0.25) -> HelicalDesign:
    r"""Propose the lightest helical spring of ``material`` for a designed spring.

    Args:
        stiffness: rate ``k`` [N/m] (> 0).
        free_length: ``l0`` [m]: the extension spring's length at which its tension is its
            initial tension, or the compression spring's free length.
        max_length: longest working length [m] (extension: largest stretch).
        max_force: largest force magnitude over the workspace [N].
        kind: ``"extension"`` (machine hooks) or ``"compression"`` (squared and ground ends).
        min_length: shortest working length [m]; a compression spring's solid length must not
            exceed it (default ``l0 - max_force/k``); for an extension spring it is only reported.
        index_range: allowed spring index ``C = D/d`` (Shigley recommends 4–12; 4–15 by default).
        min_active_coils: fewest active coils (Shigley recommends ≥ 3).
        wire_diameters: candidate wires [m] (default: preferred sizes within the material's range).
        coil_step: active coils come in steps of this (quarter turns by default); the mean coil
            diameter is then chosen so that ``G d⁴/(8 D³ n)`` is exactly ``k``.

    For each wire ``d`` and number of coils ``n`` the mean diameter is
    :math:`D = (G d^4 / (8 n k))^{1/3}`. A candidate is feasible when its index lies in
    ``index_range``, its Wahl-corrected stress at ``max_force`` does not exceed the allowable
    stress, and its length fits: extension springs need a coil free length
    ``2(D - d) + d(n + 1) ≤ l0``; compression springs a solid length ``d(n + 2) ≤ min_length``.
    The lightest feasible candidate is returned; if there is none, the result has
    ``feasible = False`` and ``reasons`` says which requirement no candidate meets.
    """
    material = material_named(material)
    kind = _kind(kind)
    k, l0, length_max, force = float(stiffness), float(free_length), float(max_length), abs(float(max_force))
    if not (np.isfinite(k) and k > 0):
        raise InputError(f"helical sizing needs a stiffness > 0, got {stiffness}")
    if not (l0 > 0 and length_max > 0):
        raise InputError(f"helical sizing needs positive lengths, got free length {free_length}, max length {max_length}")
    if min_length is None:
        min_length = l0 - force / k if kind == "compression" else l0
    design = HelicalDesign(False, kind, material.name, k, l0, length_max, float(min_length), force)
    low_d, high_d = material.diameter_range
    wires = np.array([d for d in wire_diameters if low_d - 1e-12 <= d <= high_d + 1e-12])
    if kind == "compression" and min_length <= 0:
        design.reasons.append(f"the shortest working length {min_length:.4g} m leaves no room for a coil")
        return design
    if wires.size == 0:
        design.reasons.append(f"no candidate wire in the material's range {low_d * 1e3:g}–{high_d * 1e3:g} mm")
        return design
    G = material.shear_modulus
    c_low, c_high = float(index_range[0]), float(index_range[1])
    # Coils from n_min up to the count at which the index falls to its lower limit.
    n_max = float(np.max(G * wires / (8 * c_low**3 * k)))
    n_min = float(min_active_coils)
    if n_max < n_min:
        design.reasons.append(f"rate {k:.4g} N/m is too stiff: even a {high_d * 1e3:g} mm wire at index {c_low:g} "
                              f"gives fewer than {n_min:g} active coils")
        return design
    steps = int(np.floor((min(n_max, 5000.0) - n_min) / coil_step)) + 1
    coils = n_min + coil_step * np.arange(max(steps, 1))
    d, n = np.meshgrid(wires, coils, indexing="ij")
    D = (G * d**4 / (8 * n * k)) ** (1.0 / 3.0)
    C = D / d
    stress = shear_stress(force, d, D)
    allowable = material.allowable_stress(d, kind)
    if kind == "extension":
        length = 2 * (D - d) + d * (n + 1)     # coil free length with machine hooks [m]
        fits = length <= l0 * (1 + 1e-12)
        total = n + 2.0                         # wire of the two hooks ≈ two coils
    else:
        length = d * (n + 2)                    # solid length, squared and ground [m]
        fits = length <= min_length * (1 + 1e-12)
        total = n + 2.0
    in_index = (C >= c_low - 1e-9) & (C <= c_high + 1e-9)
    strong = stress <= allowable * (1 + 1e-12)
    feasible = in_index & strong & fits
    wire_length = math.pi * D * total
    mass = material.density * wire_length * math.pi * d**2 / 4
    if not np.any(feasible):
        if not np.any(in_index):
            design.reasons.append(f"no wire of {low_d * 1e3:g}–{high_d * 1e3:g} mm gives index {c_low:g}–{c_high:g} "
                                  f"at {k:.4g} N/m with ≥ {n_min:g} coils")
        elif not np.any(in_index & strong):
            best = float(np.max(np.where(in_index, allowable / stress, 0.0)))
            design.reasons.append(f"stress: at {force:.4g} N every wire within index {c_low:g}–{c_high:g} exceeds the "
                                  f"allowable stress of {material.label} (best candidate reaches "
                                  f"{100 / best:.0f} % of allowable)")
        if np.any(in_index & strong) and not np.any(in_index & strong & fits):
            shortest = float(np.min(np.where(in_index & strong, length, np.inf)))
            if kind == "extension":
                design.reasons.append(f"length: the shortest coil strong enough is {shortest * 1e3:.1f} mm long "
                                      f"(hooks included), more than the free length {l0 * 1e3:.1f} mm")
            else:
                design.reasons.append(f"length: the shortest solid length of a coil strong enough is "
                                      f"{shortest * 1e3:.1f} mm, more than the shortest working length "
                                      f"{min_length * 1e3:.1f} mm")
        if not design.reasons:
            design.reasons.append("no candidate satisfies index, stress and length together")
        return design
    flat = int(np.argmin(np.where(feasible, mass, np.inf)))
    i, j = np.unravel_index(flat, mass.shape)
    design.feasible = True
    design.wire_diameter, design.mean_diameter, design.index = float(d[i, j]), float(D[i, j]), float(C[i, j])
    design.active_coils, design.total_coils = float(n[i, j]), float(total[i, j])
    if kind == "extension":
        design.solid_length = float(d[i, j] * (n[i, j] + 1))
        design.coil_free_length = float(length[i, j])
    else:
        design.solid_length = float(length[i, j])
        design.coil_free_length = l0
    design.wire_length, design.mass = float(wire_length[i, j]), float(mass[i, j])
    design.wahl_factor = float(wahl_factor(C[i, j]))
    design.stress, design.allowable_stress = float(stress[i, j]), float(allowable[i, j])
    design.tensile_strength = float(material.tensile_strength(d[i, j]))
    design.rate = float(spring_rate(G, d[i, j], D[i, j], n[i, j]))
    if kind == "extension" and design.coil_free_length < l0 * (1 - 1e-9):
        design.notes.append(f"the coil is {1e3 * (l0 - design.coil_free_length):.1f} mm shorter than l0: "
                            "lengthen a hook or add a link")
    if kind == "compression":
        # Shigley Eq. (10-13): absolute stability of squared-and-ground ends between flat plates (α = 0.5)
        critical = 2.63 * design.mean_diameter / 0.5
        if l0 >= critical:
            design.notes.append(f"free length {l0 * 1e3:.0f} mm ≥ {critical * 1e3:.0f} mm: the spring may buckle; "
                                "guide it on a rod or in a tube")
    return design
