r"""Constant-force element (docs/model.md §3.5): a spool or a cylinder on a large reservoir."""

from __future__ import annotations

import numpy as np

from springbalance.springs.laws.two_point import TwoPointSpring
from springbalance.springs.values import Parameters, ValueT


class ConstantForceSpring(TwoPointSpring):
    r"""Constant-force element (pneumatic spring on a large reservoir, cable on a constant-force spool):

    .. math:: F = F_0,\qquad V_s = F_0 L .

    Parameter: ``force`` F0 [N], positive when it pulls the ends together (a spool), negative
    when it pushes (a cylinder). Options as :class:`TwoPointSpring`; ``min_length`` /
    ``max_length`` give its stroke.
    """

    kind = "constant_force"
    parameter_units = {"force": "N"}
    linear_parameters = ("force",)

    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        return parameters["force"] + 0 * length  # [N]

    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        return parameters["force"] * length  # [N]·[m] = [J]

    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """Exact: ``F = F0`` (``k = 0``)."""
        return 0.0, float(values["force"]), 0.0
