"""The bookkeeping of a torque model: the design vector (:class:`DesignVariables`) and the blocks of
constraint rows (:class:`ConstraintBlock`)."""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass
class DesignVariables:
    """The design vector ``x`` in physical units: names, bounds and first guess."""

    names: list[str] = dataclasses.field(default_factory=list)
    units: list[str] = dataclasses.field(default_factory=list)
    lower: list[float] = dataclasses.field(default_factory=list)
    upper: list[float] = dataclasses.field(default_factory=list)
    start: list[float] = dataclasses.field(default_factory=list)

    def add(self, name: str, unit: str, lower: float, upper: float, start: float) -> int:
        self.names.append(name)
        self.units.append(unit)
        self.lower.append(float(lower))
        self.upper.append(float(upper))
        self.start.append(float(start))
        return len(self.names) - 1

    @property
    def size(self) -> int:
        return len(self.names)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return np.array(self.lower), np.array(self.upper)


@dataclasses.dataclass(frozen=True)
class ConstraintBlock:
    """Rows of one practical constraint of one spring (or, with ``spring == ""``, of the problem,
    such as ``no_joint_worse.<joint>``): N rows, one per sample, ``≥ 0``."""

    spring: str | None  # the spring's name (None for an unnamed spring given to TorqueModel itself)
    name: str
    unit: str
    offset: int  # first row of this block in the per-sample constraint vector
    scale: float  # typical size of a violation [unit], for the solver's scaling
    #: False when the row does not depend on the sample (a coil's index, its initial tension): the
    #: NLP then keeps it once instead of once per sample
    per_sample: bool = True
    #: the part of the row the optimisation keeps in reserve [unit]: the rule itself holds where
    #: ``row + reserve ≥ 0`` (a coil's stress reserve, :data:`~springbalance.springs.laws.coil.STRESS_RESERVE`)
    reserve: float = 0.0
    #: True for a row of no sample that the solver evaluates once from the design, not in every sample's
    #: function (the constraint says so: a coil's fatigue damage rows, costly and of four variables)
    once: bool = False
    #: True for a bound over the samples (a coil's fatigue floor or ceiling, ``P_i - F_lo ≥ 0``): only the rows
    #: of its extreme samples bind, so the solver's working set starts with those, not with the spread samples'
    extreme: bool = False
