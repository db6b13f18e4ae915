r"""Linear extension spring with initial tension (docs/model.md §3.1)."""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np

from springbalance.errors import InputError
from springbalance.springs import constraints as practical
from springbalance.springs.helical_option import HELICAL_OPTION, Helical
from springbalance.springs.laws.spring import StretchRatio, _positive_option
from springbalance.springs.laws.two_point import HelicalSpringMixin, TwoPointSpring
from springbalance.springs.params import Anchor
from springbalance.springs.values import Parameters, ValueT


class ExtensionSpring(HelicalSpringMixin, TwoPointSpring):
    r"""Linear extension spring with initial tension:

    .. math:: F = F_0 + k (L - l_0),\qquad V_s = F_0 (L - l_0) + k (L - l_0)^2 / 2 .

    Parameters: ``stiffness`` k [N/m], ``free_length`` l0 [m], ``initial_tension`` F0 [N]
    (default 0). Options: ``keep_tension`` (default True: ``L ≥ l0`` at every sample, a
    coil spring cannot be compressed below its free length), ``max_stretch`` ratio ρ
    (``L ≤ ρ l0``), ``max_force`` [N], ``max_length`` / ``min_length`` [m], ``mass``, and
    ``helical`` (:class:`~springbalance.springs.sizing.Helical`: a helical extension spring of that
    material and index with hooks must fit the free length and carry the force).
    """

    kind = "extension"
    ideal: ClassVar[bool | None] = True
    required_options: ClassVar[tuple[str, ...]] = ("ideal",)
    parameter_units = {"stiffness": "N/m", "free_length": "m", "initial_tension": "N"}
    nonnegative = ("stiffness", "free_length", "initial_tension")
    defaults = {"initial_tension": 0.0}
    linear_parameters = ("stiffness", "initial_tension")
    option_types = {
        **TwoPointSpring.option_types,
        "ideal": Literal[True],
        "keep_tension": bool,
        "max_stretch": StretchRatio | None,
        "helical": HELICAL_OPTION | None,  # type: ignore[operator]  # typeshed's ForwardRef lacks __or__
    }
    helical_kind: ClassVar[str | None] = "extension"

    def __init__(
        self,
        a: Anchor,
        b: Anchor,
        name: str | None = None,
        *,
        ideal: bool = True,
        keep_tension: bool = True,
        max_stretch: float | None = None,
        helical: Helical | dict | None = None,
        **kwargs: Any,
    ):
        if ideal is not True:
            raise InputError(
                f"{type(self).__name__} {name or ''}: this is the ideal law; a coil is "
                f"Helical{type(self).__name__} (or type: extension without ideal: true)"
            )
        super().__init__(a, b, name, **kwargs)
        self.keep_tension = bool(keep_tension)
        self.max_stretch = _positive_option(self, "max_stretch", max_stretch)
        if self.max_stretch is not None and self.max_stretch <= 1:
            raise InputError(f"spring {name or ''}: max_stretch is a ratio L/l0 and must exceed 1, got {max_stretch}")
        self._set_helical(helical)

    def free_length_interval(self, lengths: np.ndarray) -> tuple[float, float]:
        """``max L / ρ ≤ l0`` (stretch limit) and ``l0 ≤ min L`` (stays in tension)."""
        low = float(np.max(lengths)) / self.max_stretch if self.max_stretch is not None else -np.inf
        high = float(np.min(lengths)) if self.keep_tension else np.inf
        return low, high

    def tension(self, length: ValueT, parameters: Parameters) -> ValueT:
        stretch = length - parameters["free_length"]  # [m]
        return parameters["initial_tension"] + parameters["stiffness"] * stretch  # [N]

    def potential(self, length: ValueT, parameters: Parameters) -> ValueT:
        stretch = length - parameters["free_length"]  # [m]
        return stretch * (parameters["initial_tension"] + 0.5 * parameters["stiffness"] * stretch)  # [J]

    def constraints(self) -> list:
        rows = super().constraints()
        if self.keep_tension:
            rows.insert(0, practical.StaysInTension())
        if self.max_stretch is not None:
            rows.append(practical.MaxStretch(self.max_stretch))
        return rows + self._helical_constraints()

    def options(self) -> dict:
        record = super().options()
        if self.ideal:
            record["ideal"] = True
        record["keep_tension"] = self.keep_tension
        if self.max_stretch is not None:
            record["max_stretch"] = self.max_stretch
        if self.helical is not None:
            record["helical"] = self.helical.to_dict()
        return record

    def tendon_law(self, values: dict, lengths: np.ndarray) -> tuple[float, float, float]:
        """Exact: ``F = k L + (F0 - k l0)``."""
        k, l0, f0 = values["stiffness"], values["free_length"], values["initial_tension"]
        return float(k), float(f0 - k * l0), 0.0

    def law_warnings(self, values: dict, lengths: np.ndarray, tolerance: float = 1e-6) -> list[str]:
        """Below its free length a real extension spring goes slack (or solid); the linear law pushes."""
        warnings = []
        free = values["free_length"]
        slack = int(np.sum(lengths < free - tolerance))
        if slack:
            option = "keep_tension is false" if not self.keep_tension else "keep_tension is violated"
            warnings.append(
                f"spring {self.name!r} (extension) is shorter than its free length l0 = {free:.6g} m at "
                f"{slack} of {lengths.size} workspace samples (shortest {lengths.min():.6g} m; {option}): a real "
                "extension spring goes slack there, while the exported MuJoCo tendon spring (like springbalance's "
                "law) keeps the linear law and pushes"
            )
        return warnings + super().law_warnings(values, lengths, tolerance)
