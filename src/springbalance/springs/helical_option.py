r"""The ``helical`` spring option: a design must be realisable as a helical spring of a chosen index.

:class:`Helical` is the option behind the optimisation constraints of
:mod:`springbalance.springs.constraints` (see :meth:`Helical.fitting_wire`); :func:`helical_from_dict`
reads it from a record ``{material?, index?, min_active_coils?}``. Every quantity is in SI units
(m, N, Pa).
"""

from __future__ import annotations

import math
import typing
from typing import Any

import numpy as np

from springbalance.errors import InputError
from springbalance.springs.helical_formulas import wahl_factor
from springbalance.springs.materials import Material, material_named, spring_kind


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

    def __init__(self, material: str | Material = "music_wire", index: float = 8.0, min_active_coils: float = 3.0):
        self.material = material_named(material)
        index, min_active_coils = float(index), float(min_active_coils)
        if not 4.0 <= index <= 15.0:
            raise InputError(f"helical spring index C = D/d must lie in 4–15, got {index}")
        if not min_active_coils >= 1.0:
            raise InputError(f"helical spring min_active_coils must be ≥ 1, got {min_active_coils}")
        self.index, self.min_active_coils = index, min_active_coils

    def coil_length(self, wire_diameter: Any, stiffness: Any, kind: str) -> Any:
        """Free length (extension, hooks included) or solid length (compression) [m] of the coil
        with wire ``d`` and rate ``k`` (``n = G d / (8 C³ k)`` active coils)."""
        body = self.material.shear_modulus * wire_diameter**2 / (8 * self.index**3 * stiffness)  # d·n [m]
        return body + (2 * self.index - 1 if spring_kind(kind) == "extension" else 2.0) * wire_diameter

    def fitting_wire(self, room: Any, stiffness: Any, kind: str) -> Any:
        r"""Largest wire diameter [m] whose coil fits in length ``room`` [m] (root of
        :math:`a d^2 + b d = \mathrm{room}` with :math:`a = G/(8C^3 k)`), written
        :math:`2\,\mathrm{room}\,k / (b k + \sqrt{b^2 k^2 + 4 G\,\mathrm{room}\,k/(8C^3)})` so that it
        stays finite as ``k`` → 0."""
        b = 2 * self.index - 1 if spring_kind(kind) == "extension" else 2.0
        c = self.material.shear_modulus / (8 * self.index**3)  # G/(8C³) [Pa]
        return (
            2 * room * stiffness / (b * stiffness + (b * b * stiffness * stiffness + 4 * c * room * stiffness) ** 0.5)
        )

    def allowable_force(self, wire_diameter: Any, kind: str) -> Any:
        """Largest axial force [N] a wire of diameter ``d`` carries at this index."""
        fraction = self.material.allowable_fraction[spring_kind(kind)]
        stress_area = self.material.strength_power(wire_diameter, 2.0)  # S_ut d² [N]
        return math.pi * fraction * stress_area / (8 * wahl_factor(self.index) * self.index)

    def coil_wire(self, stiffness: Any) -> Any:
        """Smallest wire diameter [m] that gives ``min_active_coils`` coils at rate ``k``."""
        return 8 * self.index**3 * stiffness * self.min_active_coils / self.material.shear_modulus

    @property
    def max_stiffness(self) -> float:
        """Largest rate [N/m] with ``min_active_coils`` coils on the material's thickest wire."""
        return (
            self.material.shear_modulus * self.material.diameter_range[1] / (8 * self.index**3 * self.min_active_coils)
        )

    def to_dict(self) -> dict:
        """The record ``{material, index, min_active_coils}`` (:func:`helical_from_dict` reads it back)."""
        return {"material": self.material.name, "index": self.index, "min_active_coils": self.min_active_coils}

    def __repr__(self) -> str:
        return f"Helical({self.material.name!r}, index={self.index}, min_active_coils={self.min_active_coils})"


#: The type of the ``helical`` option in the config schema: a forward reference to the pydantic
#: record :class:`springbalance.springs.options.HelicalOption`, which the schema resolves (so that
#: the spring laws load without pydantic).
HELICAL_OPTION = typing.ForwardRef("HelicalOption", module="springbalance.springs.options")


def helical_from_dict(record: Any, where: str = "helical") -> Helical:
    """``{material?, index?, min_active_coils?}`` → :class:`Helical`."""
    if isinstance(record, Helical):
        return record
    if not isinstance(record, dict):
        raise InputError(f"{where}: expected a mapping {{material, index, min_active_coils}}, got {record!r}")
    unknown = [key for key in record if key not in ("material", "index", "min_active_coils")]
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r}; valid keys: material, index, min_active_coils")
    try:
        return Helical(
            record.get("material", "music_wire"),
            _number(record.get("index", 8.0), f"{where}.index"),
            _number(record.get("min_active_coils", 3.0), f"{where}.min_active_coils"),
        )
    except InputError as error:
        raise InputError(f"{where}: {error}") from None


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise InputError(f"{where}: expected a finite number, got {value!r}")
    return float(value)
