"""Practical constraints on a spring (MODEL.md §6), one small class each.

Each constraint produces, for every workspace sample, rows that must be ``≥ 0`` at a
feasible design. They are written with plain arithmetic so that the same code evaluates
CasADi expressions (inside the NLP) and NumPy arrays (when checking a design).
Bounds on stiffness and free length are variable bounds (:class:`~springbalance.params.Free`).
"""

from __future__ import annotations

import dataclasses


@dataclasses.dataclass(frozen=True)
class StaysInTension:
    """A tension spring never goes slack: ``L - l0 ≥ 0`` at every sample [m]."""

    name = "tension"
    unit = "m"
    scale = 0.1  # [m] typical size of a violation, for the solver's scaling

    def rows(self, length, force, parameters):
        return length - parameters["free_length"]


@dataclasses.dataclass(frozen=True)
class MaxStretch:
    """A spring is not stretched beyond ``ratio`` times its free length: ``ρ l0 - L ≥ 0`` [m]."""

    ratio: float
    name = "max_stretch"
    unit = "m"
    scale = 0.1  # [m]

    def rows(self, length, force, parameters):
        return self.ratio * parameters["free_length"] - length


@dataclasses.dataclass(frozen=True)
class MaxForce:
    """The spring force stays within ``limit`` in magnitude: ``F_max - |F| ≥ 0`` [N].

    Written as ``F_max² - F² ≥ 0`` scaled by ``1/F_max`` so that it is smooth.
    """

    limit: float
    name = "max_force"
    unit = "N"

    @property
    def scale(self):
        return self.limit  # [N]

    def rows(self, length, force, parameters):
        return (self.limit * self.limit - force * force) / self.limit


@dataclasses.dataclass(frozen=True)
class MaxLength:
    """The spring (with its fittings) is never longer than ``limit``: ``L_max - L ≥ 0`` [m]."""

    limit: float
    name = "max_length"
    unit = "m"

    @property
    def scale(self):
        return self.limit  # [m]

    def rows(self, length, force, parameters):
        return self.limit - length


@dataclasses.dataclass(frozen=True)
class MinLength:
    """The spring is never shorter than ``limit``: ``L - L_min ≥ 0`` [m]."""

    limit: float
    name = "min_length"
    unit = "m"

    @property
    def scale(self):
        return self.limit  # [m]

    def rows(self, length, force, parameters):
        return length - self.limit
