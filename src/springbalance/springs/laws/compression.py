r"""Compression spring with preload (docs/model.md §3.3): pushes its ends apart."""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np

from springbalance.errors import InputError
from springbalance.springs import constraints as practical
from springbalance.springs.helical_option import HELICAL_OPTION, Helical
from springbalance.springs.laws.spring import PositiveNumber, _positive_option
from springbalance.springs.laws.two_point import HelicalSpringMixin, TwoPointSpring
from springbalance.springs.params import Anchor
from springbalance.springs.values import Parameters, ValueT


class CompressionSpring(HelicalSpringMixin, TwoPointSpring):
    r"""Compression spring: pushes its ends apart (negative tension), preload ``F0`` at length ``l0``:

    .. math:: F = -\bigl(F_0 + k (l_0 - L)\bigr),\qquad V_s = F_0 (l_0 - L) + k (l_0 - L)^2 / 2 .

    Parameters: ``stiffness`` k [N/m], ``free_length`` l0 [m] (the length at which it pushes
    with ``F0``: a coil's free length, a gas spring's extended length), ``preload`` F0 [N]
    (default 0). Options: ``stays_compressed`` (default True: ``L ≤ l0`` at every sample, the
    spring stays in contact), ``stroke`` [m] (``L ≥ l0 - stroke``: it cannot be compressed
    further), ``max_force``, ``max_length`` / ``min_length``, ``mass``, and ``helical`` (a helical
    compression spring of that material and index must carry the force without going solid).
    """

    kind = "compression"
    ideal: ClassVar[bool | None] = True
    required_options: ClassVar[tuple[str, ...]] = ("ideal",)
    parameter_units = {"stiffness": "N/m", "free_length": "m", "preload": "N"}
    nonnegative = ("stiffness", "free_length", "preload")
    defaults = {"preload": 0.0}
    linear_parameters = ("stiffness", "preload")
    option_types = {
        **TwoPointSpring.option_types,
        "ideal": Literal[True],
        "stays_compressed": bool,
        "stroke": PositiveNumber | None,
        "helical": HELICAL_OPTION | None,  # type: ignore[operator]  # typeshed's ForwardRef lacks __or__
    }
    helical_kind: ClassVar[str | None] = "compression"

    def __init__(
        self,
        a: Anchor,
        b: Anchor,
        name: str | None = None,
        *,
        ideal: bool = True,
        stays_compressed: bool = True,
        stroke: float | None = None,
        helical: Helical | dict | None = None,
        **kwargs: Any,
    ):
        if ideal is not True:
            raise InputError(
                f"{type(self).__name__} {name or ''}: this is the ideal law; a coil is "
                f"Helical{type(self).__name__} (or type: compression without ideal: true)"
            )
        super().__init__(a, b, name, **kwargs)
        self.stays_compressed = bool(stays_compressed)
        self.stroke = _positive_option(self, "stroke", stroke)
        self._set_helical(helical)

    def free_length_interval(self, lengths: np.ndarray) -> tuple[float, float]:
        """``max L ≤ l0`` (stays compressed) and ``l0 ≤ min L + stroke`` (stroke limit)."""
        low = float(np.max(lengths)) if self.stays_compressed else -np.inf
        high = float(np.min(lengths)) + self.stroke if self.stroke is not None else np.inf
        return low, high

    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        compression = parameters["free_length"] - length  # [m]
        return -(parameters["preload"] + parameters["stiffness"] * compression)  # [N], pushes

    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        compression = parameters["free_length"] - length  # [m]
        return compression * (parameters["preload"] + 0.5 * parameters["stiffness"] * compression)  # [J]

    def constraints(self) -> list:
        rows = super().constraints()
        if self.stays_compressed:
            rows.insert(0, practical.StaysCompressed())
        if self.stroke is not None:
            rows.append(practical.Stroke(self.stroke))
        return rows + self._helical_constraints()

    def options(self) -> dict:
        record = super().options()
        if self.ideal:
            record["ideal"] = True
        record["stays_compressed"] = self.stays_compressed
        if self.stroke is not None:
            record["stroke"] = self.stroke
        if self.helical is not None:
            record["helical"] = self.helical.to_dict()
        return record

    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """Exact: ``F = k (L - l0) - F0 = k L - (F0 + k l0)``."""
        k, l0, f0 = values["stiffness"], values["free_length"], values["preload"]
        return float(k), float(-f0 - k * l0), 0.0

    def law_warnings(self, values: dict, lengths: np.ndarray, tolerance: float = 1e-6) -> list[str]:
        """Longer than ``l0`` a real spring loses contact (a gas spring stops); beyond its stroke it bottoms out."""
        warnings = []
        free, kind = values["free_length"], self.kind
        longer = int(np.sum(lengths > free + tolerance))
        if longer:
            what = "stops at its extended length" if kind == "gas" else "loses contact"
            warnings.append(
                f"spring {self.name!r} ({kind}) is longer than its free length l0 = {free:.6g} m at {longer} of "
                f"{lengths.size} workspace samples (longest {lengths.max():.6g} m): a real {kind} spring {what} there, "
                "while the exported MuJoCo tendon spring keeps the linear law and pulls"
            )
        if self.stroke is not None:
            beyond = int(np.sum(lengths < free - self.stroke - tolerance))
            if beyond:
                warnings.append(
                    f"spring {self.name!r} ({kind}) is compressed beyond its stroke {self.stroke:.6g} m at {beyond} "
                    f"of {lengths.size} workspace samples (shortest {lengths.min():.6g} m, limit "
                    f"{free - self.stroke:.6g} m): a real one bottoms out there, the exported MuJoCo tendon spring "
                    "keeps the linear law"
                )
        return warnings + super().law_warnings(values, lengths, tolerance)
