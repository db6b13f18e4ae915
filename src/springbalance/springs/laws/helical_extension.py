r"""Helical extension spring (docs/model.md §3.8): a close-wound coil with machine hooks, designed by its
geometry. This is what ``type: extension`` means unless the record says ``ideal: true``.

The design variables are the coil itself: wire diameter ``d`` [m], mean coil diameter ``D`` [m],
active coils ``n`` [1] and initial tension ``F_i`` [N] (Shigley ch. 10). Rate and free length follow:

.. math::

    k = \frac{G d^4}{8 D^3 n}, \qquad L_b = d (n + 1), \qquad l_0 = L_b + 2 (D - d),

(body length ``L_b`` of the closed coil, two machine hooks of inside diameter ``D - d``), and the law
is the extension law: :math:`F = F_i + k (L - l_0)`, :math:`V_s = (L - l_0)(F_i + k (L - l_0)/2)`.
The rules of a buildable coil are constraints of the optimisation, at every workspace sample:

- body stress :math:`K_B\,8 F D/(\pi d^3) \le f_{body} S_{ut}(d)` (Bergsträsser factor
  :math:`K_B = (4C + 2)/(4C - 3)`, :math:`S_{ut} = A/d^m`, ``f_body`` 45 % for carbon steel);
- hook bending at section A and torsion at section B within 75 % and 40 % of :math:`S_{ut}`
  (:func:`~springbalance.springs.helical_formulas.hook_bending_stress`, :func:`~springbalance.springs.helical_formulas.hook_torsion_stress`);
- index :math:`C = D/d` within ``index_range`` (default 4–12); outer diameter :math:`D + d` within
  ``max_outer_diameter`` when given;
- initial tension within the band that can be wound at that index
  (:func:`~springbalance.springs.helical_formulas.initial_stress_band`);
- ``L ≥ l_0`` (the coil never goes slack, ``keep_tension``), with
  :data:`~springbalance.springs.laws.coil.LENGTH_RESERVE` (1 mm) kept in reserve.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from springbalance.springs.helical_formulas import hook_bending_stress, hook_torsion_stress, initial_stress_band
from springbalance.springs.laws.coil import CHECK_TOLERANCE, LENGTH_RESERVE, MPA, HelicalCoilSpring
from springbalance.springs.params import Anchor
from springbalance.springs.values import Parameters, ValueT


class ExtensionCoilRules:
    """The rows of a buildable helical extension spring at one sample, ``≥ 0`` when the rule holds
    (stresses as a fraction of their allowable [1], the initial stress in MPa)."""

    name = "coil"

    def __init__(self, spring: HelicalExtensionSpring):
        self.spring = spring
        parts = [("tension", "m", 0.01)] if spring.keep_tension else []
        parts += [("body_stress", "1", 0.1), ("hook_bending", "1", 0.1), ("hook_torsion", "1", 0.1)]
        if spring.winds:
            parts += [("initial_tension_low", "MPa", 10.0), ("initial_tension_high", "MPa", 10.0)]
        self.parts = tuple(parts + spring.common_parts())
        #: the stress rows keep ``stress_reserve`` of their allowable in reserve [1], the length rule
        #: :data:`~springbalance.springs.laws.coil.LENGTH_RESERVE` [m]
        self.reserves = dict.fromkeys(("body_stress", "hook_bending", "hook_torsion"), spring.stress_reserve)
        if spring.keep_tension:
            self.reserves["tension"] = LENGTH_RESERVE

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        spring, material = self.spring, self.spring.material
        d, D = parameters["wire_diameter"], parameters["mean_diameter"]
        strength = material.tensile_strength(d)  # S_ut [Pa]
        low, high = initial_stress_band(D / d)  # [Pa]
        initial = 8 * parameters["initial_tension"] * D / (math.pi * d**3)  # τ_i [Pa]
        rows = [length - spring.free_length(parameters) - LENGTH_RESERVE] if spring.keep_tension else []
        usable = 1 - spring.stress_reserve  # [1]
        rows += [
            usable - spring.body_stress(force, parameters) / (material.allowable_fraction["extension"] * strength),
            usable - hook_bending_stress(force, d, D) / (material.hook_fraction["bending"] * strength),
            usable - hook_torsion_stress(force, d, D) / (material.hook_fraction["torsion"] * strength),
        ]
        if spring.winds:
            rows += [(initial - low) / MPA, (high - initial) / MPA]
        return rows + spring.common_rows(parameters)


class HelicalExtensionSpring(HelicalCoilSpring):
    r"""A helical extension spring with machine hooks, designed by its wire, coil and initial tension.

    Args:
        a: the anchor of one end.
        b: the anchor of the other end.
        name: the spring's name.
        keep_tension: ``L ≥ l0`` at every sample (default True: below ``l0`` the coil is slack).
        **kwargs (Any): the parameters ``wire_diameter`` d [m], ``mean_diameter`` D [m],
            ``active_coils`` n [1] and ``initial_tension`` F_i [N], each a number or
            :class:`~springbalance.springs.params.Free` (defaults: the material's wire range, the
            index range over it, 3–200 coils, 0–2000 N); the options ``material`` (default
            music wire), ``max_outer_diameter`` [m], ``index_range`` (default ``[4, 12]``),
            ``own_mass`` (default True) and those of :class:`~springbalance.springs.laws.base.TwoPointSpring`.
    """

    kind = "extension"
    parameter_units = {"wire_diameter": "m", "mean_diameter": "m", "active_coils": "1", "initial_tension": "N"}
    nonnegative = ("wire_diameter", "mean_diameter", "active_coils", "initial_tension")
    #: every parameter may be left out: its bounds then follow from the material and the envelope
    defaults = dict.fromkeys(("wire_diameter", "mean_diameter", "active_coils", "initial_tension"))
    option_types = {**HelicalCoilSpring.option_types, "keep_tension": bool}
    helical_kind = "extension"
    end_type = "machine hooks"
    default_bounds = {"active_coils": (3.0, 200.0), "initial_tension": (0.0, 2000.0)}

    def __init__(self, a: Anchor, b: Anchor, name: str | None = None, *, keep_tension: bool = True, **kwargs: Any):
        self.keep_tension = bool(keep_tension)
        super().__init__(a, b, name, **kwargs)

    def free_length(self, values: Mapping[str, ValueT]) -> ValueT:
        """``l0 = d (n + 1) + 2 (D − d)`` [m]: the closed body and two machine hooks."""
        d, D, n = values["wire_diameter"], values["mean_diameter"], values["active_coils"]
        return d * (n + 1) + 2 * (D - d)

    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        stretch = length - self.free_length(parameters)  # [m]
        return parameters["initial_tension"] + self.rate(parameters) * stretch  # [N]

    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        stretch = length - self.free_length(parameters)  # [m]
        return stretch * (parameters["initial_tension"] + 0.5 * self.rate(parameters) * stretch)  # [J]

    def derived_values(self, values: dict) -> dict:
        """The extension law of this coil: ``stiffness`` [N/m], ``free_length`` [m], ``initial_tension`` [N]."""
        return {
            "stiffness": float(self.rate(values)),
            "free_length": float(self.free_length(values)),
            "initial_tension": float(values["initial_tension"]),
        }

    def constraints(self) -> list:
        return [ExtensionCoilRules(self), *self.fatigue_constraints()] + super().constraints()

    def options(self) -> dict:
        return {**super().options(), "keep_tension": self.keep_tension}

    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """Exact: ``F = k L + (F_i − k l0)``."""
        law = self.derived_values(values)
        return law["stiffness"], law["initial_tension"] - law["stiffness"] * law["free_length"], 0.0

    def law_warnings(self, values: dict, lengths: np.ndarray, tolerance: float = 1e-6) -> list[str]:
        free = float(self.free_length(values))
        slack = int(np.sum(lengths < free - tolerance))
        warnings = []
        if slack:
            warnings.append(
                f"spring {self.name!r} (helical extension) is shorter than its free length l0 = {free:.6g} m at {slack} "
                f"of {lengths.size} workspace samples: the coil is slack there, while the exported MuJoCo tendon "
                "spring keeps the linear law and pushes"
            )
        return warnings + super().law_warnings(values, lengths, tolerance)

    def spec_sheet(self, values: dict, lengths: np.ndarray, forces: np.ndarray) -> dict:
        """The part's data sheet over the workspace and its buildable verdict, checked from the numbers.

        ``values``: the parameter values [SI]; ``lengths`` [m] and ``forces`` [N]: its length and
        tension at every sample. Every failed rule is one entry of ``reasons``.
        """
        lengths, forces = np.asarray(lengths, dtype=float), np.asarray(forces, dtype=float)
        initial_tension = float(values["initial_tension"])
        largest = max(float(np.max(forces)) if forces.size else initial_tension, initial_tension)  # [N]
        sheet, reasons = self.common_sheet(values, largest)
        d, D = sheet["wire_diameter"], sheet["mean_diameter"]
        strength = float(self.material.tensile_strength(d))
        slack = 1 + CHECK_TOLERANCE
        for mode, stress in (
            ("bending", hook_bending_stress(largest, d, D)),
            ("torsion", hook_torsion_stress(largest, d, D)),
        ):
            allowable = self.material.hook_fraction[mode] * strength
            sheet[f"hook_{mode}_stress"], sheet[f"hook_{mode}_allowable"] = float(stress), allowable
            if stress > allowable * slack:
                reasons.append(
                    f"hook {mode} stress {stress / MPA:.0f} MPa exceeds the allowable {allowable / MPA:.0f} MPa"
                )
        low, high = (float(v) for v in initial_stress_band(D / d))
        initial_stress = 8 * initial_tension * D / (math.pi * d**3)  # [Pa]
        if self.winds and not low - 10 * CHECK_TOLERANCE * MPA <= initial_stress <= high + 10 * CHECK_TOLERANCE * MPA:
            reasons.append(
                f"initial tension {initial_tension:.4g} N (stress {initial_stress / MPA:.0f} MPa) outside the "
                f"band that can be wound at index {D / d:.2f}: {low / MPA:.0f}–{high / MPA:.0f} MPa"
            )
        free = float(self.free_length(values))
        if lengths.size and float(np.min(lengths)) < free * (1 - CHECK_TOLERANCE):
            reasons.append(
                f"shortest length {np.min(lengths) * 1e3:.1f} mm is below the free length {free * 1e3:.1f} mm: "
                "the coil goes slack"
            )
        self.fatigue_sheet(sheet, forces, reasons)
        d_, n = sheet["wire_diameter"], sheet["active_coils"]
        sheet.update(
            {
                "free_length": free,
                "body_length": d_ * (n + 1),
                "initial_tension": initial_tension,
                "longest_length": float(np.max(lengths)) if lengths.size else free,
                "shortest_length": float(np.min(lengths)) if lengths.size else free,
                "buildable": not reasons,
                "reasons": reasons,
            }
        )
        return sheet
