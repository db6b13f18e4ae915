"""The pydantic records of the spring options that are mappings: ``helical`` and a coil ``mass``.

They live in their own module, the only one of :mod:`springbalance.springs` that imports pydantic,
so that the spring laws, and with them the design problem, load without pydantic. A law names
them in its ``option_types`` by the forward references
:data:`springbalance.springs.sizing.HELICAL_OPTION` and :data:`springbalance.springs.mass.COIL_MASS_RECORD`;
the config schema (:mod:`springbalance.io.schema`) resolves those, which imports this module when
a config is validated or the schema written.
"""

from __future__ import annotations

from typing import Annotated, Literal, Optional, Union

import annotated_types
import pydantic

_Positive = Annotated[float, annotated_types.Gt(0)]


class HelicalOption(pydantic.BaseModel):
    """The keys of the ``helical`` option of a spring record (see :class:`Helical`)."""

    model_config = pydantic.ConfigDict(extra="forbid")

    material: str = pydantic.Field("music_wire", description="a material of MATERIALS")
    index: Annotated[float, annotated_types.Ge(4), annotated_types.Le(15)] = pydantic.Field(
        8.0, description="spring index C = D/d [1], 4–15"
    )
    min_active_coils: Annotated[float, annotated_types.Ge(1)] = pydantic.Field(3.0, description="[1]")


class CoilMassRecord(pydantic.BaseModel):
    """The keys of a coil mass: ``{coil_diameter, active_coils, wire_length?, material? | shear_modulus, density}``."""

    model_config = pydantic.ConfigDict(extra="forbid")

    coil_diameter: _Positive = pydantic.Field(description="mean coil diameter D [m]")
    active_coils: _Positive = pydantic.Field(description="active coils n [1]")
    wire_length: Optional[_Positive] = pydantic.Field(None, description="wire length L_w [m]; default π D (n + 2)")
    material: Optional[str] = pydantic.Field(None, description="a material of springbalance.springs.sizing.MATERIALS")
    shear_modulus: Optional[_Positive] = pydantic.Field(None, description="G [Pa], instead of a material")
    density: Optional[_Positive] = pydantic.Field(None, description="ρ [kg/m³], instead of a material")


class DutyOption(pydantic.BaseModel):
    """The keys of a coil's ``duty`` (docs/model.md §3.8.2): what it must survive; fatigue is then a rule."""

    model_config = pydantic.ConfigDict(extra="forbid")

    cycles: Union[Annotated[float, annotated_types.Ge(1)], Literal["infinite"]] = pydantic.Field(
        1e6, description="load cycles the coil must live [1], or 'infinite' (Zimmerli's endurance data)"
    )
    peened: bool = pydantic.Field(False, description="shot-peened wire (compression springs only)")
    reliability: float = pydantic.Field(
        0.5,
        description="probability the fatigue data hold; factor k_e of Shigley Table 6-5 (0.5: 1.0)",
        json_schema_extra={"enum": [0.5, 0.9, 0.95, 0.99, 0.999, 0.9999]},
    )
    safety_factor: Annotated[float, annotated_types.Ge(1)] = pydantic.Field(
        1.2, description="fatigue safety factor n_f every location must reach [1]"
    )
    criterion: Literal["gerber", "goodman", "sines"] = pydantic.Field(
        "gerber", description="how the fatigue data are projected to zero mean stress"
    )
