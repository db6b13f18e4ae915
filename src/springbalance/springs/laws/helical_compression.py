r"""Helical compression spring (docs/model.md §3.8): squared-and-ground ends, designed by its geometry.
This is what ``type: compression`` means unless the record says ``ideal: true``.

The design variables are wire diameter ``d`` [m], mean coil diameter ``D`` [m], active coils ``n``
[1] and free length ``l_0`` [m] (the pitch is free). With ``n + 2`` total coils (Shigley Table 10-1):

.. math::

    k = \frac{G d^4}{8 D^3 n}, \qquad L_s = d (n + 2), \qquad
    F = -k (l_0 - L), \qquad V_s = k (l_0 - L)^2 / 2 ,

so it pushes its ends apart (negative tension) and has no preload at its free length: a preload
comes from mounting it shorter than ``l_0``. The rules are constraints at every sample: body stress
:math:`K_B\,8 |F| D/(\pi d^3) \le f\,S_{ut}(d)` (45 % for music wire); the solid length
:math:`L_s \le L` (it never closes solid); ``L ≤ l_0`` (it stays in contact, ``stays_compressed``);
no buckling, :math:`l_0 \le 2.63 D/\alpha` with :math:`\alpha = 0.5` for ends between flat parallel
plates (Shigley Eq. 10-13), unless ``guided`` (on a rod or in a tube); index and envelope as every coil.
The optimisation keeps :data:`~springbalance.springs.laws.coil.LENGTH_RESERVE` (1 mm) in reserve on both
length rules, ``L_s + 1 mm ≤ L ≤ l_0 − 1 mm``: they bind on the boundary of the joint box (the shortest and
the longest length), where the verification searches them, as an extension coil's ``L ≥ l_0``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from springbalance.springs.laws.coil import CHECK_TOLERANCE, LENGTH_RESERVE, HelicalCoilSpring
from springbalance.springs.params import Anchor
from springbalance.springs.values import Parameters, ValueT

#: end-condition constant α of squared-and-ground ends between flat parallel surfaces (Shigley Table 10-2)
END_CONSTANT = 0.5


class CompressionCoilRules:
    """The rows of a buildable helical compression spring at one sample, ``≥ 0`` when the rule holds."""

    name = "coil"

    def __init__(self, spring: HelicalCompressionSpring):
        self.spring = spring
        parts = [("stays_compressed", "m", 0.01)] if spring.stays_compressed else []
        parts += [("solid", "m", 0.01), ("body_stress", "1", 0.1)]
        if not spring.guided:
            parts.append(("buckling", "m", 0.01))
        self.parts = tuple(parts + spring.common_parts())
        #: the stress row keeps ``stress_reserve`` of its allowable in reserve [1], the length rows
        #: :data:`~springbalance.springs.laws.coil.LENGTH_RESERVE` [m]
        self.reserves = {"body_stress": spring.stress_reserve, "solid": LENGTH_RESERVE}
        if spring.stays_compressed:
            self.reserves["stays_compressed"] = LENGTH_RESERVE

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        spring, material = self.spring, self.spring.material
        d, D, n = parameters["wire_diameter"], parameters["mean_diameter"], parameters["active_coils"]
        free = parameters["free_length"]
        allowable = material.allowable_fraction["compression"] * material.tensile_strength(d)  # [Pa]
        rows = [free - length - LENGTH_RESERVE] if spring.stays_compressed else []
        rows += [
            length - d * (n + 2) - LENGTH_RESERVE,
            1 - spring.stress_reserve - spring.body_stress(-force, parameters) / allowable,
        ]
        if not spring.guided:
            rows.append(2.63 * D / END_CONSTANT - free)
        return rows + spring.common_rows(parameters)


class HelicalCompressionSpring(HelicalCoilSpring):
    r"""A helical compression spring with squared-and-ground ends, designed by its wire, coil and free length.

    Args:
        a: the anchor of one end.
        b: the anchor of the other end.
        name: the spring's name.
        stays_compressed: ``L ≤ l0`` at every sample (default True).
        guided: the spring runs on a rod or in a tube, so buckling is not checked (default False).
        **kwargs (Any): the parameters ``wire_diameter`` d [m], ``mean_diameter`` D [m],
            ``active_coils`` n [1] and ``free_length`` l0 [m], each a number or
            :class:`~springbalance.springs.params.Free` (defaults: the material's wire range, the
            index range over it, 3–100 coils, 0.01–1 m); the options ``material``,
            ``max_outer_diameter`` [m], ``index_range``, ``own_mass`` and those of
            :class:`~springbalance.springs.laws.base.TwoPointSpring`.
    """

    kind = "compression"
    parameter_units = {"wire_diameter": "m", "mean_diameter": "m", "active_coils": "1", "free_length": "m"}
    nonnegative = ("wire_diameter", "mean_diameter", "active_coils", "free_length")
    #: every parameter may be left out: its bounds then follow from the material and the envelope
    defaults = dict.fromkeys(("wire_diameter", "mean_diameter", "active_coils", "free_length"))
    option_types = {**HelicalCoilSpring.option_types, "stays_compressed": bool, "guided": bool}
    helical_kind = "compression"
    end_type = "squared and ground"
    default_bounds = {"active_coils": (3.0, 100.0), "free_length": (0.01, 1.0)}

    def __init__(
        self,
        a: Anchor,
        b: Anchor,
        name: str | None = None,
        *,
        stays_compressed: bool = True,
        guided: bool = False,
        **kwargs: Any,
    ):
        self.stays_compressed, self.guided = bool(stays_compressed), bool(guided)
        super().__init__(a, b, name, **kwargs)

    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        return -self.rate(parameters) * (parameters["free_length"] - length)  # [N], pushes

    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        compression = parameters["free_length"] - length  # [m]
        return 0.5 * self.rate(parameters) * compression * compression  # [J]

    def derived_values(self, values: dict) -> dict:
        """The compression law of this coil: ``stiffness`` [N/m], ``free_length`` [m], ``preload`` 0 [N]."""
        return {"stiffness": float(self.rate(values)), "free_length": float(values["free_length"]), "preload": 0.0}

    def constraints(self) -> list:
        return [CompressionCoilRules(self), *self.fatigue_constraints()] + super().constraints()

    def options(self) -> dict:
        return {**super().options(), "stays_compressed": self.stays_compressed, "guided": self.guided}

    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """Exact: ``F = k L − k l0``."""
        law = self.derived_values(values)
        return law["stiffness"], -law["stiffness"] * law["free_length"], 0.0

    def law_warnings(self, values: dict, lengths: np.ndarray, tolerance: float = 1e-6) -> list[str]:
        free = float(values["free_length"])
        longer = int(np.sum(lengths > free + tolerance))
        warnings = []
        if longer:
            warnings.append(
                f"spring {self.name!r} (helical compression) is longer than its free length l0 = {free:.6g} m at "
                f"{longer} of {lengths.size} workspace samples: it loses contact there, while the exported MuJoCo "
                "tendon spring keeps the linear law and pulls"
            )
        return warnings + super().law_warnings(values, lengths, tolerance)

    def spec_sheet(self, values: dict, lengths: np.ndarray, forces: np.ndarray) -> dict:
        """The part's data sheet over the workspace and its buildable verdict, checked from the numbers."""
        lengths, forces = np.asarray(lengths, dtype=float), np.asarray(forces, dtype=float)
        largest = float(np.max(-forces)) if forces.size else 0.0  # [N] push
        sheet, reasons = self.common_sheet(values, max(largest, 0.0))
        d, D, n = sheet["wire_diameter"], sheet["mean_diameter"], sheet["active_coils"]
        free, solid = float(values["free_length"]), d * (n + 2)
        shortest = float(np.min(lengths)) if lengths.size else free
        longest = float(np.max(lengths)) if lengths.size else free
        if solid > shortest * (1 + CHECK_TOLERANCE):
            reasons.append(f"solid length {solid * 1e3:.1f} mm exceeds the shortest length {shortest * 1e3:.1f} mm")
        if self.stays_compressed and longest > free * (1 + CHECK_TOLERANCE):
            reasons.append(
                f"longest length {longest * 1e3:.1f} mm exceeds the free length {free * 1e3:.1f} mm: "
                "the spring loses contact"
            )
        critical = 2.63 * D / END_CONSTANT
        if not self.guided and free > critical * (1 + CHECK_TOLERANCE):
            reasons.append(
                f"free length {free * 1e3:.0f} mm above the buckling limit {critical * 1e3:.0f} mm; "
                "guide it (guided: true) or shorten it"
            )
        self.fatigue_sheet(sheet, forces, reasons)
        sheet.update(
            {
                "free_length": free,
                "body_length": free,
                "solid_length": solid,
                "initial_tension": 0.0,
                "longest_length": longest,
                "shortest_length": shortest,
                "buckling_length": critical,
                "buildable": not reasons,
                "reasons": reasons,
            }
        )
        return sheet
