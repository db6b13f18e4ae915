r"""The checks of a chosen stock part beyond its static rules: fatigue under the spring's duty, and its
tolerance box with the adjuster travel (docs/guides/coils-and-stock.md, "Stock springs").

A stock part in a design is a fixed helical coil, so the static rules of its use (stresses, hooks,
solid length, buckling) are constraints of the re-optimisation like those of a designed coil. Two
more checks follow from its force over the workspace, at the optimum of its candidate solve:

- **fatigue** (:func:`springbalance.springs.fatigue.fatigue_margins`): the force magnitude cycles
  between :math:`F_{min}` and :math:`F_{max}` (:func:`~springbalance.springs.fatigue.force_range`),
  and every location (body; an extension part's hook A bending and hook B torsion) must reach the
  duty's safety factor :math:`n_f` at its cycles. A candidate that does not is not chosen;
- **tolerance** (:func:`springbalance.design.tolerance.analyse_tolerance`): the part's box of rate,
  initial tension (or preload) and free length under the design's tolerances (a config's ``tolerance``
  section; grade 2 of EN 15800 / DIN 2097 by default), the worst residual over the boxes of all springs, and the travel
  of the preload screw that restores the balance.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from springbalance.design.problem import DesignProblem
from springbalance.design.tolerance import ToleranceAnalysis, analyse
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.errors import InputError
from springbalance.springs.fatigue import Duty, Margin, duty_from_record, fatigue_margins, force_range
from springbalance.springs.laws import Spring
from springbalance.springs.laws.coil import HelicalCoilSpring

__all__ = ["PartFatigue", "fatigue_of", "spring_duty", "tolerance_of"]


def spring_duty(spring: Spring) -> Duty:
    """The duty of ``spring`` (its ``duty`` when it has one), else the default :class:`Duty` (10⁶ cycles)."""
    duty = getattr(spring, "duty", None)
    return Duty() if duty is None else duty_from_record(duty)


@dataclasses.dataclass(frozen=True)
class PartFatigue:
    """The fatigue verdict of a part: the duty, its force range ``min_force``/``max_force`` [N] (magnitudes)
    and the :class:`~springbalance.springs.fatigue.Margin` of each location."""

    duty: Duty
    min_force: float
    max_force: float
    margins: dict[str, Margin]

    @property
    def holds(self) -> bool:
        """Every location reaches the duty's safety factor."""
        return all(margin.holds for margin in self.margins.values())

    def failing(self) -> str:
        """The locations below the required factor, ``"hook_bending n_f 0.91 < 1.2"``, joined by commas."""
        return ", ".join(
            f"{margin.location} n_f {margin.safety_factor:.3g} < {margin.required:g}"
            for margin in self.margins.values()
            if not margin.holds
        )

    def line(self) -> str:
        """One line: the duty, then n_f and the life of each location."""
        cycles = "infinite life" if np.isinf(self.duty.cycles) else f"{self.duty.cycles:.0e} cycles"
        locations = ", ".join(
            f"{margin.location} n_f {margin.safety_factor:.3g} ({margin.life_text()})"
            for margin in self.margins.values()
        )
        verdict = "ok" if self.holds else "FAILS"
        return (
            f"fatigue {verdict} ({cycles}, {self.duty.criterion}, n_f ≥ {self.duty.safety_factor:g}; force "
            f"{self.min_force:.4g} … {self.max_force:.4g} N): {locations}"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "duty": self.duty.to_dict(),
            "min_force": self.min_force,
            "max_force": self.max_force,
            "holds": self.holds,
            "locations": {name: margin.to_dict() for name, margin in self.margins.items()},
        }


def fatigue_of(problem: DesignProblem, x: np.ndarray, tensions: np.ndarray, name: str, duty: Duty) -> PartFatigue:
    """The fatigue of spring ``name`` (a helical coil) of ``problem`` at design ``x`` whose tensions over the
    samples are ``tensions`` (N×n_s) [N]."""
    column = [spring.name for spring in problem.springs].index(name)
    spring = problem.springs[column]
    if not isinstance(spring, HelicalCoilSpring):
        raise InputError(f"spring {name!r} ({spring.kind}) is not a helical coil: it has no fatigue data")
    kind = str(spring.kind)
    values = problem.model.spring_values(spring, x)
    low, high = force_range(tensions[:, column], kind)
    margins = fatigue_margins(
        float(values["wire_diameter"]), float(values["mean_diameter"]), spring.material, low, high, duty.to_dict(), kind
    )
    return PartFatigue(duty, low, high, margins)


def tolerance_of(
    problem: DesignProblem, x: np.ndarray, tau: np.ndarray, lengths: np.ndarray, spec: ToleranceSpec | None = None
) -> ToleranceAnalysis:
    """The tolerance analysis of design ``x`` (residual ``tau`` N×nv, lengths N×n_s) under ``spec`` (the
    design's, e.g. a config's ``tolerance`` section; None: grade 2 for every coil)."""
    return analyse(problem, x, tau, lengths, spec or ToleranceSpec())
