r"""Zero-free-length spring (docs/model.md §3.2): the law of exact balance."""

from __future__ import annotations

import numpy as np

from springbalance.springs.laws.two_point import TwoPointSpring
from springbalance.springs.values import Parameters, ValueT


class ZeroFreeLengthSpring(TwoPointSpring):
    r"""Zero-free-length spring: :math:`F = k L`, :math:`V_s = k L^2 / 2`.

    Parameters: ``stiffness`` k [N/m].
    """

    kind = "zero_free_length"
    parameter_units = {"stiffness": "N/m"}
    nonnegative = ("stiffness",)
    linear_parameters = ("stiffness",)

    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        return parameters["stiffness"] * length  # [N/m]·[m] = [N]

    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        return 0.5 * parameters["stiffness"] * length * length  # [N/m]·[m²] = [J]

    def potential_of_square(self, square: ValueT, parameters: Parameters) -> ValueT:
        """``k L² / 2`` from ``L²`` [m²]: its derivative stays finite where the ends meet (``L = 0``)."""
        return 0.5 * parameters["stiffness"] * square  # [N/m]·[m²] = [J]

    def tension_per_length(self, length: ValueT, parameters: Parameters) -> ValueT:
        return parameters["stiffness"] + 0 * length  # smooth at L = 0

    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """Exact: ``F = k L`` (``k``, ``c = 0``)."""
        return float(values["stiffness"]), 0.0, 0.0
