r"""The mass of a spring itself (docs/model.md §5): fixed, or coupled to its rate through the coil.

A spring's mass is carried as a uniform body between its ends, half at each end; see
:class:`~springbalance.springs.laws.base.TwoPointSpring`. In a record, ``mass`` is a number [kg]
(:class:`FixedMass`) or a coil mapping (:class:`CoilMass`, whose keys
:class:`~springbalance.springs.options.CoilMassRecord` lists).
"""

from __future__ import annotations

import math
import typing
from typing import Annotated, Union

import annotated_types
import numpy as np

from springbalance.errors import InputError
from springbalance.springs.helical_formulas import coil_mass
from springbalance.springs.materials import material_named
from springbalance.springs.values import Parameters, Value

#: The pydantic record of a coil mass in the config schema, by forward reference (resolved by the
#: schema, so that the spring laws load without pydantic): :class:`springbalance.springs.options.CoilMassRecord`.
COIL_MASS_RECORD = typing.ForwardRef("CoilMassRecord", module="springbalance.springs.options")


#: the type of the ``mass`` option in the config schema: kilograms, or a coil.
# a runtime ForwardRef, resolved by pydantic when the schema is built: mypy cannot read it as a type
MassOption = Union[Annotated[float, annotated_types.Ge(0)], COIL_MASS_RECORD]  # type: ignore[valid-type]


class CoilMass:
    r"""Mass of a helical spring whose wire diameter follows its rate (docs/model.md §5).

    A coil of fixed mean diameter ``D`` [m] and ``n`` active coils has rate
    :math:`k = G d^4 / (8 D^3 n)`; its wire of length ``L_w`` [m] weighs

    .. math:: m_s = \rho \pi L_w \sqrt{D^3 n k / (2 G)}  \quad [kg],

    so a stiffer spring of the same geometry is heavier. ``shear_modulus`` G [Pa] and
    ``density`` rho [kg/m³] come from ``material`` (see :data:`springbalance.springs.sizing.MATERIALS`)
    unless given. ``wire_length`` defaults to :math:`\pi D (n + 2)` (two end coils or hooks).
    """

    def __init__(
        self,
        coil_diameter: float,
        active_coils: float,
        wire_length: float | None = None,
        material: str | None = None,
        shear_modulus: float | None = None,
        density: float | None = None,
    ):
        self.material = None if material is None else material_named(material).name
        if material is not None:
            found = material_named(material)
            shear_modulus = found.shear_modulus if shear_modulus is None else shear_modulus
            density = found.density if density is None else density
        if shear_modulus is None or density is None:
            raise InputError("CoilMass needs shear_modulus and density, or a material")
        values = {
            "coil_diameter": coil_diameter,
            "active_coils": active_coils,
            "shear_modulus": shear_modulus,
            "density": density,
        }
        if wire_length is not None:
            values["wire_length"] = wire_length
        for key, value in values.items():
            if (
                isinstance(value, bool)
                or not isinstance(value, (int, float, np.floating, np.integer))
                or not np.isfinite(value)
                or value <= 0
            ):
                raise InputError(f"CoilMass {key} must be a positive number, got {value!r}")
        self.coil_diameter, self.active_coils = float(coil_diameter), float(active_coils)  # [m], [1]
        self.shear_modulus, self.density = float(shear_modulus), float(density)  # [Pa], [kg/m³]
        self.wire_length = (
            float(wire_length) if wire_length is not None else math.pi * self.coil_diameter * (self.active_coils + 2)
        )  # [m]

    couples_stiffness = True

    def value(self, parameters: Parameters) -> Value:
        """``m_s`` [kg] for the spring's parameter values (uses ``stiffness``)."""
        return coil_mass(
            parameters["stiffness"],
            self.coil_diameter,
            self.active_coils,
            self.wire_length,
            self.shear_modulus,
            self.density,
        )

    def wire_diameter(self, stiffness: Value) -> Value:
        """``d = (8 D³ n k / G)^(1/4)`` [m]."""
        return (8 * self.coil_diameter**3 * self.active_coils * stiffness / self.shear_modulus) ** 0.25

    def to_dict(self) -> dict:
        record: dict[str, float | str] = {
            "coil_diameter": self.coil_diameter,
            "active_coils": self.active_coils,
            "wire_length": self.wire_length,
            "shear_modulus": self.shear_modulus,
            "density": self.density,
        }
        if self.material is not None:
            record["material"] = self.material
        return record

    def __repr__(self) -> str:
        return (
            f"CoilMass(D={self.coil_diameter}, n={self.active_coils}, L_w={self.wire_length}, "
            f"G={self.shear_modulus:g}, rho={self.density:g})"
        )


class FixedMass:
    """A spring mass that does not depend on the design [kg]."""

    couples_stiffness = False

    def __init__(self, mass: float):
        if (
            isinstance(mass, bool)
            or not isinstance(mass, (int, float, np.floating, np.integer))
            or not np.isfinite(mass)
            or mass < 0
        ):
            raise InputError(f"spring mass must be a number ≥ 0 [kg], got {mass!r}")
        self.mass = float(mass)

    def value(self, parameters: Parameters) -> Value:
        return self.mass

    def to_dict(self) -> float:
        return self.mass

    def __repr__(self) -> str:
        return f"FixedMass({self.mass})"


_COIL_MASS_KEYS = ("coil_diameter", "active_coils", "wire_length", "material", "shear_modulus", "density")


def mass_from_record(
    value: float | dict | CoilMass | FixedMass | None, where: str = "mass"
) -> CoilMass | FixedMass | None:
    """``m`` [kg] (fixed) or ``{coil_diameter, active_coils, wire_length?, material? | shear_modulus, density}``."""
    if value is None or isinstance(value, (FixedMass, CoilMass)):
        return value
    try:
        if isinstance(value, dict):
            unknown = [key for key in value if key not in _COIL_MASS_KEYS]
            if unknown:
                raise InputError(f"unknown key {unknown[0]!r}; valid keys: {', '.join(_COIL_MASS_KEYS)}")
            for key in ("coil_diameter", "active_coils"):
                if key not in value:
                    raise InputError(f"missing key {key!r}")
            return CoilMass(**value)
        return FixedMass(value)
    except InputError as error:
        raise InputError(f"{where}: {error}") from None
