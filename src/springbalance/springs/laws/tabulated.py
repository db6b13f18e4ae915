r"""Tabulated spring (docs/model.md §3.7): a measured force–length curve, such as a catalogue gas
spring with a progressive curve, an elastomer or a bungee.

The table lists points ``(x_i, f_i)`` of a part's length [m] and tension [N] (positive pulls,
negative pushes), with ``x_0 < x_1 < … < x_{n-1}``. Between the points the force is linear; beyond
the ends it continues with the end segments' slopes. With the segment slopes
``s_i = (f_{i+1} - f_i)/(x_{i+1} - x_i)`` and ``ramp(y) = max(y, 0) = (y + |y|)/2``:

.. math::

    f(x) = f_0 + s_0 (x - x_0) + \sum_{i=1}^{n-2} (s_i - s_{i-1})\,\mathrm{ramp}(x - x_i),

    F(L) = \sigma f(L - \delta), \qquad
    V_s(L) = \sigma \Bigl[f_0 (x - x_0) + \tfrac12 s_0 (x - x_0)^2
             + \tfrac12 \sum_{i=1}^{n-2} (s_i - s_{i-1})\,\mathrm{ramp}(x - x_i)^2\Bigr]_{x = L - \delta},

so ``dV_s/dL = F`` everywhere and ``V_s`` is zero at ``L = x_0 + δ``. Parameters: ``scale`` σ [1]
≥ 0 (parts in parallel, or a family of parts with one curve shape; the torque is linear in it)
and ``shift`` δ [m] (the mounting offset: rod ends, an adjustable eye). Options: ``table``
(required), ``stays_in_table`` (default true: ``x_0 ≤ L - δ ≤ x_{n-1}`` at every sample, the part is
only known there) and those of every two-point spring. The law is written with ``abs``, so the same
code evaluates CasADi symbols and NumPy arrays; it is continuous with a continuous first derivative
of the potential, piecewise smooth in the force.
"""

from __future__ import annotations

import dataclasses
from typing import Annotated, Any, Sequence

import annotated_types
import numpy as np

from springbalance.errors import InputError
from springbalance.springs.laws.two_point import TwoPointSpring
from springbalance.springs.params import Anchor
from springbalance.springs.values import Parameters, ValueT

#: the type of the ``table`` option in the config schema: at least two [length m, force N] rows.
TableOption = Annotated[list[Annotated[list[float], annotated_types.Len(2, 2)]], annotated_types.MinLen(2)]


def _ramp(value: ValueT) -> ValueT:
    """``max(value, 0)`` with plain arithmetic (CasADi and NumPy alike)."""
    return 0.5 * (value + abs(value))


@dataclasses.dataclass(frozen=True)
class StaysInTable:
    """The part works inside its table: ``(L - δ) - x_0 ≥ 0`` and ``x_{n-1} - (L - δ) ≥ 0`` [m]."""

    low: float
    high: float
    name = "in_table"
    unit = "m"
    parts = (("in_table_low", "m", 0.1), ("in_table_high", "m", 0.1))

    def rows(self, length: ValueT, force: ValueT, parameters: Parameters) -> ValueT | list[ValueT]:
        x = length - parameters["shift"]  # [m]
        return [x - self.low, self.high - x]


class TabulatedSpring(TwoPointSpring):
    r"""Spring with the force–length curve of a table (piecewise linear, linear beyond the ends).

    Args:
        a: the anchor of one end.
        b: the anchor of the other end.
        name: the spring's name.
        table (numpy.typing.ArrayLike): rows ``[length [m], force [N]]`` with strictly
            increasing lengths (at least two).
        stays_in_table: add the constraint ``x_0 ≤ L - δ ≤ x_{n-1}`` (default True).
        **kwargs (Any): the parameters ``scale`` σ [1] ≥ 0, number or
            :class:`~springbalance.springs.params.Free` (default 1), and ``shift`` δ [m], the
            table's lengths are ``L - δ`` (default 0); and the options of
            :class:`~springbalance.springs.laws.base.TwoPointSpring`.
    """

    kind = "tabulated"
    parameter_units = {"scale": "1", "shift": "m"}
    nonnegative = ("scale",)
    defaults = {"scale": 1.0, "shift": 0.0}
    linear_parameters = ("scale",)
    option_types = {**TwoPointSpring.option_types, "table": TableOption, "stays_in_table": bool}
    required_options = ("table",)

    def __init__(
        self,
        a: Anchor,
        b: Anchor,
        name: str | None = None,
        *,
        table: Sequence[Sequence[float]] | None = None,
        stays_in_table: bool = True,
        **kwargs: Any,
    ):
        super().__init__(a, b, name, **kwargs)
        self.table = _checked_table(table, self._label())
        self.stays_in_table = bool(stays_in_table)
        lengths, forces = self.table[:, 0], self.table[:, 1]
        self.slopes = np.diff(forces) / np.diff(lengths)  # s_i [N/m]
        self.kinks = lengths[1:-1]  # x_1 … x_{n-2} [m]
        self.slope_changes = np.diff(self.slopes)  # s_i - s_{i-1} [N/m]

    def _curve(self, x: ValueT) -> tuple[ValueT, ValueT]:
        """``f(x)`` [N] and ``∫_{x_0}^{x} f`` [J] of the table at table length ``x`` [m]."""
        x0, f0, s0 = self.table[0, 0], self.table[0, 1], self.slopes[0]
        offset = x - x0  # [m]
        force = f0 + s0 * offset  # [N]
        energy = offset * (f0 + 0.5 * s0 * offset)  # [J]
        for kink, change in zip(self.kinks, self.slope_changes):
            past = _ramp(x - kink)  # [m]
            force = force + change * past
            energy = energy + 0.5 * change * past * past
        return force, energy

    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        force, _ = self._curve(length - parameters["shift"])
        return parameters["scale"] * force  # [N]

    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        _, energy = self._curve(length - parameters["shift"])
        return parameters["scale"] * energy  # [J]

    def constraints(self) -> list:
        rows = super().constraints()
        if self.stays_in_table:
            rows.insert(0, StaysInTable(float(self.table[0, 0]), float(self.table[-1, 0])))
        return rows

    def options(self) -> dict:
        record = super().options()
        record["table"] = self.table.tolist()
        record["stays_in_table"] = self.stays_in_table
        return record

    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """A straight table is exact: ``F = σ s_0 L + σ (f_0 - s_0 (x_0 + δ))``; a curve gets its best line."""
        if np.all(np.abs(self.slope_changes) <= 1e-12 * np.max(np.abs(self.slopes), initial=1.0)):
            scale, shift = values["scale"], values["shift"]
            (x0, f0), s0 = self.table[0], self.slopes[0]
            return float(scale * s0), float(scale * (f0 - s0 * (x0 + shift))), 0.0
        return super().tendon_law(values, lengths)

    def law_warnings(self, values: dict, lengths: np.ndarray, tolerance: float = 1e-6) -> list[str]:
        """Outside its table a real part is unknown (or at its stop); the law continues linearly."""
        warnings = []
        x = np.asarray(lengths) - values["shift"]
        outside = int(np.sum((x < self.table[0, 0] - tolerance) | (x > self.table[-1, 0] + tolerance)))
        if outside:
            warnings.append(
                f"spring {self.name!r} (tabulated) leaves its table [{self.table[0, 0]:.6g}, {self.table[-1, 0]:.6g}] m "
                f"at {outside} of {np.size(lengths)} workspace samples: the law is extrapolated linearly there"
            )
        return warnings + super().law_warnings(values, lengths, tolerance)


def _checked_table(table: Any, label: str) -> np.ndarray:
    if table is None:
        raise InputError(f"{label}: missing key 'table' (rows [length, force] of the force–length curve)")
    try:
        rows = np.array(table, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{label}: table must be rows [length [m], force [N]], got {table!r}") from None
    if rows.ndim != 2 or rows.shape[1] != 2 or rows.shape[0] < 2:
        raise InputError(f"{label}: table must have at least two rows [length [m], force [N]], got {table!r}")
    if not np.all(np.isfinite(rows)):
        raise InputError(f"{label}: table holds a value that is not finite: {table!r}")
    steps = np.diff(rows[:, 0])
    if np.any(steps <= 0):
        row = int(np.argmax(steps <= 0)) + 1
        raise InputError(
            f"{label}: table lengths must increase strictly; row {row} has length {rows[row, 0]:g} m "
            f"after {rows[row - 1, 0]:g} m"
        )
    return rows
