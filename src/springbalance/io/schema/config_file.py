"""The record of a whole config file: its sections, each validated by its own record.

The record is rebuilt (:func:`config_model`) when a spring law registers itself, so that the
``springs`` section takes every law of :data:`springbalance.springs.SPRING_TYPES`.
"""

from __future__ import annotations

import functools
from typing import Any, Optional

import pydantic
from pydantic import ConfigDict, Field

from springbalance.io.schema.fields import REQUIRED_SECTIONS, Objective, Record, fail
from springbalance.io.schema.records import (
    ClearanceRecord,
    MassBound,
    MechanismRecord,
    ScenariosRecord,
    SolveRecord,
    Weights,
    WorkspaceRecord,
)
from springbalance.io.schema.spring_records import spring_list
from springbalance.springs import SPRING_TYPES

#: the title of the config's JSON Schema.
TITLE = "springbalance config"


#: the ``tolerance`` section: checked by :meth:`springbalance.design.tolerance_spec.ToleranceSpec.from_record`
TOLERANCE_FIELD: tuple[Any, Any] = (
    Optional[dict[str, Any]],
    Field(
        None,
        description="the springs' tolerances (docs/guides/tolerances.md): {grade: 1|2|3} (EN 15800 / "
        "DIN 2097; grade 2 by default) or explicit ± {rate [fraction], initial_tension [N], free_length [m]}; "
        "adjuster_travel [m]: the preload screws' travel, checked in the report; robust: true designs for the "
        "box's corners (corners: exact|strong_weak|uniform), each re-balanced within adjuster_travel",
    ),
)


class _ConfigBase(Record):
    """A springbalance config: the arm, its workspace, the springs to design, and how to design them.

    Units are SI (m, N, N/m, rad, kg, m/s²); with workspace.degrees, angles of revolute joints in the
    workspace section are in degrees. Relative paths are relative to the config file's folder."""

    model_config = ConfigDict(
        title=TITLE,
        json_schema_extra={
            "description": " ".join(
                "A springbalance config: the arm, its workspace, the springs to design, and how to design them. Units are SI "
                "(m, N, N/m, rad, kg, m/s²); with workspace.degrees, angles of revolute joints in the workspace section are "
                "in degrees. Relative paths are relative to the config file's folder.".split()
            )
        },
    )

    @classmethod
    def _check_record(cls, data: dict) -> None:
        for section in REQUIRED_SECTIONS:
            if section not in data:
                raise fail("missing_section", f"missing section {section!r} (required: {', '.join(REQUIRED_SECTIONS)})")


def config_model() -> type[Record]:
    """The model of a whole config file (rebuilt when a spring law registers itself)."""
    return _config_model(tuple(SPRING_TYPES.items()))


@functools.cache
def _config_model(laws: tuple) -> type[Record]:
    return pydantic.create_model(
        "ConfigRecord",
        __base__=_ConfigBase,
        __doc__=_ConfigBase.__doc__,
        __module__=__name__,
        mechanism=(MechanismRecord, Field(description="the arm (required)")),
        workspace=(
            Optional[WorkspaceRecord],
            Field(
                description="the poses over which a design is judged (required; "
                "empty means 1024 Sobol points of the URDF limits)"
            ),
        ),
        springs=(
            spring_list(laws),
            Field(
                description="the springs to design (required): one record each, the format in which designs are saved"
            ),
        ),
        objective=(
            Objective,
            Field(
                "rms",
                description="rms, peak, pe_variance, energy (needs an ordered "
                "workspace), joint_peaks (sum of the per-joint peaks) or "
                "peak_then_joints (the worst joint first, then the others)",
            ),
        ),
        weights=(
            Optional[Weights],
            Field(None, description="{joint: w ≥ 0}: joint weights of the objective; default 1 for every joint"),
        ),
        solve=(Optional[SolveRecord], Field(None, description="solver options")),
        scenarios=(Optional[ScenariosRecord], Field(None, description="load cases (payloads, mass scales)")),
        no_joint_worse=(
            bool,
            Field(
                False,
                description="constrain every joint with a weight > 0 to stay at or "
                "below its unbalanced peak torque at every sample",
            ),
        ),
        clearance=(
            Optional[ClearanceRecord],
            Field(None, description="keep every spring this far from the arm's collision geometry"),
        ),
        tolerance=TOLERANCE_FIELD,
        max_spring_mass=(
            Optional[MassBound],
            Field(
                None,
                description="upper bound [kg] on the total mass of the springs (a coil's wire, a given mass; "
                "an ideal spring without mass counts 0)",
            ),
        ),
    )
