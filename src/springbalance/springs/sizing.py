r"""Sizing a designed spring as a helical coil: the lightest wire, coil and coil count that carry it.

:func:`size_helical_spring` proposes a wire (a preferred size), a mean coil diameter and a
number of active coils for a designed ``(k, l0, max length, max force)`` and says plainly when
no helical spring of the material can do it (:class:`HelicalDesign`). For each wire ``d`` and
number of active coils ``n`` the mean diameter giving rate ``k`` [N/m] is
:math:`D = (G d^4 / (8 n k))^{1/3}` (Shigley Eq. 10-9); a candidate must keep its index
``C = D/d`` in range, its Wahl-corrected stress at the largest force under the allowable
stress [Pa], and fit in length [m]: an extension spring with machine hooks has free length
``2(D − d) + d(n + 1)`` (Shigley §10-11), a squared-and-ground compression spring has
``N_t = n + 2`` total coils and solid length ``d N_t`` (Table 10-1).

This module is also the historical home of the helical spring's other parts, which it
re-exports: the textbook relations (:mod:`springbalance.springs.helical_formulas`), the wires
(:mod:`springbalance.springs.materials`) and the ``helical`` optimisation option
(:mod:`springbalance.springs.helical_option`).

Every quantity is in SI units (m, N, Pa, kg).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Sequence, cast

import numpy as np

from springbalance.errors import InputError
from springbalance.springs.helical_formulas import (
    HOOK_SIDE_BEND_INDEX,
    MM,
    MPA,
    bergstrasser_factor,
    coil_mass,
    hook_bending_stress,
    hook_torsion_stress,
    initial_stress_band,
    shear_stress,
    spring_rate,
    wahl_factor,
)
from springbalance.springs.helical_option import HELICAL_OPTION, Helical, helical_from_dict
from springbalance.springs.materials import (
    KINDS,
    MATERIALS,
    PREFERRED_WIRE_DIAMETERS,
    Material,
    StrengthRange,
    material_named,
    spring_kind,
)

#: the names of the helical spring's other modules that this module re-exports (its former contents)
__all__ = [
    "HELICAL_OPTION",
    "HOOK_SIDE_BEND_INDEX",
    "KINDS",
    "MATERIALS",
    "MM",
    "MPA",
    "PREFERRED_WIRE_DIAMETERS",
    "Helical",
    "HelicalDesign",
    "Material",
    "StrengthRange",
    "bergstrasser_factor",
    "coil_mass",
    "helical_from_dict",
    "hook_bending_stress",
    "hook_torsion_stress",
    "initial_stress_band",
    "material_named",
    "shear_stress",
    "size_helical_spring",
    "spring_rate",
    "wahl_factor",
]


# ---------------------------------------------------------------------- sizing a designed spring
@dataclasses.dataclass
class HelicalDesign:
    """A proposed helical spring, or the plain reason why none exists.

    Lengths in m, forces in N, stresses in Pa, mass in kg.
    """

    feasible: bool
    kind: str
    material: str
    stiffness: float  # designed rate [N/m]
    free_length: float  # designed free length l0 [m]
    max_length: float  # longest working length [m]
    min_length: float  # shortest working length [m]
    max_force: float  # largest |F| [N]
    reasons: list = dataclasses.field(default_factory=list)
    wire_diameter: float = float("nan")
    mean_diameter: float = float("nan")
    index: float = float("nan")
    active_coils: float = float("nan")
    total_coils: float = float("nan")
    solid_length: float = float("nan")  # compression: d N_t; extension: closed body d (n + 1)
    coil_free_length: float = float("nan")  # extension: body + hooks; compression: l0
    wire_length: float = float("nan")
    mass: float = float("nan")
    wahl_factor: float = float("nan")
    stress: float = float("nan")  # at max_force [Pa]
    allowable_stress: float = float("nan")
    tensile_strength: float = float("nan")
    rate: float = float("nan")  # G d⁴/(8 D³ n) of the proposal [N/m]
    notes: list = dataclasses.field(default_factory=list)

    @property
    def utilisation(self) -> float:
        """Stress at max force over allowable stress."""
        return self.stress / self.allowable_stress

    def to_dict(self) -> dict:
        """The fields as a JSON-ready mapping (None for a quantity not computed, NaN in the fields)."""
        record = dataclasses.asdict(self)
        return {
            key: (None if isinstance(value, float) and not np.isfinite(value) else value)
            for key, value in record.items()
        }

    def summary(self) -> str:
        """Two or three lines of plain text."""
        head = f"helical {self.kind} spring, {MATERIALS[self.material].label if self.material in MATERIALS else self.material}"
        if not self.feasible:
            return f"{head}: NOT FEASIBLE — " + "; ".join(self.reasons)
        lines = [
            f"{head}: wire d {self.wire_diameter * 1e3:.2f} mm, mean coil D {self.mean_diameter * 1e3:.1f} mm "
            f"(index {self.index:.2f}), {self.active_coils:g} active / {self.total_coils:g} total coils, "
            f"mass {self.mass:.3g} kg",
            f"stress at {self.max_force:.4g} N: {self.stress / MPA:.0f} MPa (Wahl {self.wahl_factor:.3f}) of "
            f"{self.allowable_stress / MPA:.0f} MPa allowable ({100 * self.utilisation:.0f} %), "
            f"{'solid length' if self.kind == 'compression' else 'coil free length'} "
            f"{(self.solid_length if self.kind == 'compression' else self.coil_free_length) * 1e3:.1f} mm",
        ]
        lines += self.notes
        return "\n".join(lines)


def size_helical_spring(
    stiffness: float,
    free_length: float,
    max_length: float,
    max_force: float,
    material: str | Material = "music_wire",
    kind: str = "extension",
    min_length: float | None = None,
    index_range: Sequence[float] = (4.0, 15.0),
    min_active_coils: float = 3.0,
    wire_diameters: Sequence[float] = PREFERRED_WIRE_DIAMETERS,
    coil_step: float = 0.25,
) -> HelicalDesign:
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
    kind = spring_kind(kind)
    k, l0, length_max, force = float(stiffness), float(free_length), float(max_length), abs(float(max_force))
    if not (np.isfinite(k) and k > 0):
        raise InputError(f"helical sizing needs a stiffness > 0, got {stiffness}")
    if not (l0 > 0 and length_max > 0):
        raise InputError(
            f"helical sizing needs positive lengths, got free length {free_length}, max length {max_length}"
        )
    if min_length is None:
        min_length = l0 - force / k if kind == "compression" else l0
    design = HelicalDesign(False, kind, material.name, k, l0, length_max, float(min_length), force)
    counts = _wires_and_coils(design, material, min_length, index_range, min_active_coils, wire_diameters, coil_step)
    if counts is None:
        return design
    grid = _candidates(design, material, min_length, index_range, *counts)
    if not np.any(grid.feasible):
        _explain(design, material, grid, min_length, index_range, min_active_coils)
        return design
    _choose(design, material, grid)
    return design


@dataclasses.dataclass
class _Candidates:
    """Every candidate coil, as arrays over (wire diameter, active coils): wire ``d`` [m], active coils
    ``n``, mean diameter ``D`` [m], index ``C``, stress at the largest force and allowable stress [Pa],
    the length that must fit [m] and whether it does, total coils, the index and stress verdicts,
    wire length [m] and mass [kg]."""

    d: np.ndarray
    n: np.ndarray
    D: np.ndarray
    C: np.ndarray
    stress: np.ndarray
    allowable: np.ndarray
    length: np.ndarray
    fits: np.ndarray
    total: np.ndarray
    in_index: np.ndarray
    strong: np.ndarray
    feasible: np.ndarray
    wire_length: np.ndarray
    mass: np.ndarray


def _wires_and_coils(
    design: HelicalDesign,
    material: Material,
    min_length: float,
    index_range: Sequence[float],
    min_active_coils: float,
    wire_diameters: Sequence[float],
    coil_step: float,
) -> tuple[np.ndarray, np.ndarray] | None:
    """The candidate wires [m] (those of the material's range) and active coil counts, or None when there
    is no candidate (the reason is then in ``design.reasons``)."""
    k, kind = design.stiffness, design.kind
    low_d, high_d = material.diameter_range
    wires = np.array([d for d in wire_diameters if low_d - 1e-12 <= d <= high_d + 1e-12])
    if kind == "compression" and min_length <= 0:
        design.reasons.append(f"the shortest working length {min_length:.4g} m leaves no room for a coil")
        return None
    if wires.size == 0:
        design.reasons.append(f"no candidate wire in the material's range {low_d * 1e3:g}–{high_d * 1e3:g} mm")
        return None
    G = material.shear_modulus
    c_low = float(index_range[0])
    # Coils from n_min up to the count at which the index falls to its lower limit.
    n_max = float(np.max(G * wires / (8 * c_low**3 * k)))
    n_min = float(min_active_coils)
    if n_max < n_min:
        design.reasons.append(
            f"rate {k:.4g} N/m is too stiff: even a {high_d * 1e3:g} mm wire at index {c_low:g} "
            f"gives fewer than {n_min:g} active coils"
        )
        return None
    steps = int(np.floor((min(n_max, 5000.0) - n_min) / coil_step)) + 1
    coils = n_min + coil_step * np.arange(max(steps, 1))
    return wires, coils


def _candidates(
    design: HelicalDesign,
    material: Material,
    min_length: float,
    index_range: Sequence[float],
    wires: np.ndarray,
    coils: np.ndarray,
) -> _Candidates:
    """Every (wire, active coils) pair with the mean diameter that gives the designed rate, and its verdicts."""
    k, l0, force, kind = design.stiffness, design.free_length, design.max_force, design.kind
    G = material.shear_modulus
    c_low, c_high = float(index_range[0]), float(index_range[1])
    d, n = np.meshgrid(wires, coils, indexing="ij")
    D = (G * d**4 / (8 * n * k)) ** (1.0 / 3.0)
    C = D / d
    stress = shear_stress(force, d, D)
    allowable = cast(np.ndarray, material.allowable_stress(d, kind))  # an array of wires: an array
    if kind == "extension":
        length = 2 * (D - d) + d * (n + 1)  # coil free length with machine hooks [m]
        fits = length <= l0 * (1 + 1e-12)
        total = n + 2.0  # wire of the two hooks ≈ two coils
    else:
        length = d * (n + 2)  # solid length, squared and ground [m]
        fits = length <= min_length * (1 + 1e-12)
        total = n + 2.0
    in_index = (C >= c_low - 1e-9) & (C <= c_high + 1e-9)
    strong = stress <= allowable * (1 + 1e-12)
    feasible = in_index & strong & fits
    wire_length = math.pi * D * total
    mass = material.density * wire_length * math.pi * d**2 / 4
    return _Candidates(
        d, n, D, C, stress, allowable, length, fits, total, in_index, strong, feasible, wire_length, mass
    )


def _explain(
    design: HelicalDesign,
    material: Material,
    grid: _Candidates,
    min_length: float,
    index_range: Sequence[float],
    min_active_coils: float,
) -> None:
    """Add to ``design.reasons`` which requirement (index, stress, length) no candidate meets."""
    k, l0, force, kind = design.stiffness, design.free_length, design.max_force, design.kind
    low_d, high_d = material.diameter_range
    c_low, c_high = float(index_range[0]), float(index_range[1])
    n_min = float(min_active_coils)
    in_index, strong = grid.in_index, grid.strong
    if not np.any(in_index):
        design.reasons.append(
            f"no wire of {low_d * 1e3:g}–{high_d * 1e3:g} mm gives index {c_low:g}–{c_high:g} "
            f"at {k:.4g} N/m with ≥ {n_min:g} coils"
        )
    elif not np.any(in_index & strong):
        best = float(np.max(np.where(in_index, grid.allowable / grid.stress, 0.0)))
        design.reasons.append(
            f"stress: at {force:.4g} N every wire within index {c_low:g}–{c_high:g} exceeds the "
            f"allowable stress of {material.label} (best candidate reaches "
            f"{100 / best:.0f} % of allowable)"
        )
    if np.any(in_index & strong) and not np.any(in_index & strong & grid.fits):
        shortest = float(np.min(np.where(in_index & strong, grid.length, np.inf)))
        if kind == "extension":
            design.reasons.append(
                f"length: the shortest coil strong enough is {shortest * 1e3:.1f} mm long "
                f"(hooks included), more than the free length {l0 * 1e3:.1f} mm"
            )
        else:
            design.reasons.append(
                f"length: the shortest solid length of a coil strong enough is "
                f"{shortest * 1e3:.1f} mm, more than the shortest working length "
                f"{min_length * 1e3:.1f} mm"
            )
    if not design.reasons:
        design.reasons.append("no candidate satisfies index, stress and length together")


def _choose(design: HelicalDesign, material: Material, grid: _Candidates) -> None:
    """Fill ``design`` with the lightest feasible candidate, and its notes (a short coil, buckling)."""
    l0, kind = design.free_length, design.kind
    d, n, D, C, length, total = grid.d, grid.n, grid.D, grid.C, grid.length, grid.total
    flat = int(np.argmin(np.where(grid.feasible, grid.mass, np.inf)))
    i, j = np.unravel_index(flat, grid.mass.shape)
    design.feasible = True
    design.wire_diameter, design.mean_diameter, design.index = float(d[i, j]), float(D[i, j]), float(C[i, j])
    design.active_coils, design.total_coils = float(n[i, j]), float(total[i, j])
    if kind == "extension":
        design.solid_length = float(d[i, j] * (n[i, j] + 1))
        design.coil_free_length = float(length[i, j])
    else:
        design.solid_length = float(length[i, j])
        design.coil_free_length = l0
    design.wire_length, design.mass = float(grid.wire_length[i, j]), float(grid.mass[i, j])
    design.wahl_factor = float(wahl_factor(C[i, j]))
    design.stress, design.allowable_stress = float(grid.stress[i, j]), float(grid.allowable[i, j])
    design.tensile_strength = float(material.tensile_strength(d[i, j]))
    design.rate = float(spring_rate(material.shear_modulus, d[i, j], D[i, j], n[i, j]))
    if kind == "extension" and design.coil_free_length < l0 * (1 - 1e-9):
        design.notes.append(
            f"the coil is {1e3 * (l0 - design.coil_free_length):.1f} mm shorter than l0: lengthen a hook or add a link"
        )
    if kind == "compression":
        # Shigley Eq. (10-13): absolute stability of squared-and-ground ends between flat plates (α = 0.5)
        critical = 2.63 * design.mean_diameter / 0.5
        if l0 >= critical:
            design.notes.append(
                f"free length {l0 * 1e3:.0f} mm ≥ {critical * 1e3:.0f} mm: the spring may buckle; "
                "guide it on a rod or in a tube"
            )
