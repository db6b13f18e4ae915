r"""What every helical coil spring shares (docs/model.md §3.8): the wire, the index range, the
envelope, the design variables' default bounds and the coil's own mass.

A coil of wire diameter ``d`` [m], mean diameter ``D`` [m] and ``n`` active coils of a wire with
shear modulus ``G`` [Pa] and density ``ρ`` [kg/m³] has rate :math:`k = G d^4/(8 D^3 n)` [N/m] and
weighs :math:`m_s = \rho\,(\pi d^2/4)\,\pi D\,(n + 2)` [kg] (two end coils or hooks). The mass is
carried half at each end (docs/model.md §5) unless ``own_mass`` is false. :class:`HelicalCoilSpring`
has no ``kind``: the laws are :mod:`~springbalance.springs.laws.helical_extension` and
:mod:`~springbalance.springs.laws.helical_compression`.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, ClassVar, Literal, Mapping, Sequence

import annotated_types
import numpy as np

from springbalance.errors import InputError
from springbalance.springs.fatigue import DUTY_OPTION, Duty, duty_from_record, fatigue_margins, force_range
from springbalance.springs.fatigue_rows import FatigueRules
from springbalance.springs.helical_formulas import bergstrasser_factor
from springbalance.springs.laws.spring import PositiveNumber
from springbalance.springs.laws.two_point import TwoPointSpring
from springbalance.springs.materials import material_named
from springbalance.springs.params import Anchor, Free
from springbalance.springs.values import Parameters, Value, ValueT

MPA = 1e6
#: fraction of each allowable stress that the optimisation keeps in reserve [1]: the rules hold at the
#: workspace samples only, and a pose between samples may load a spring slightly more (the UR5
#: benchmark saw 1 % more on 4,096 unseen poses). The spec sheet's verdict uses the full allowable.
STRESS_RESERVE = 0.02
#: length [m] that a helical extension coil's rule ``L ≥ l0`` keeps in reserve in the optimisation: the rule
#: binds on the boundary of the joint box, where the verification searches it (docs/model.md, "Verification"),
#: and the least length moves along that boundary as the design changes, so a re-solve that holds ``L ≥ l0``
#: at the poses found misses the moved minimum by a fraction of a millimetre (the demo: 0.8 mm, then 0.18 mm
#: and 0.011 mm in three re-solves). 1 mm is less than DIN 2097's grade-2 free-length tolerance of any
#: extension spring longer than 40 mm (±1.1 mm), and the verification judges the rule itself, ``L ≥ l0``.
LENGTH_RESERVE = 1e-3
#: relative slack of the numeric checks of a spec sheet (the solver's feasibility tolerance is 1e-6)
CHECK_TOLERANCE = 1e-5
IndexRange = Annotated[list[Annotated[float, annotated_types.Ge(3)]], annotated_types.Len(2, 2)]


class HelicalCoilSpring(TwoPointSpring):
    """Base of the helical coil laws: material, index range, envelope, default bounds, own mass.

    Subclasses set ``kind``, ``parameter_units`` (``wire_diameter``, ``mean_diameter``,
    ``active_coils`` and their own), :meth:`coil` and the law.
    """

    ideal = False
    option_types = {
        **{key: value for key, value in TwoPointSpring.option_types.items() if key != "mass"},
        "ideal": Literal[False],
        "material": str,
        "max_outer_diameter": PositiveNumber | None,
        "index_range": IndexRange | None,
        "own_mass": bool,
        "stress_reserve": Annotated[float, annotated_types.Ge(0), annotated_types.Lt(1)],
        "duty": DUTY_OPTION | None,  # type: ignore[operator]  # typeshed's ForwardRef lacks __or__
    }
    helical_kind: ClassVar[str] = ""
    end_type: ClassVar[str] = ""
    #: default bounds of the parameters besides the wire and the coil diameter
    default_bounds: ClassVar[dict[str, tuple[float, float]]] = {"active_coils": (3.0, 200.0)}

    def __init__(
        self,
        a: Anchor,
        b: Anchor,
        name: str | None = None,
        *,
        material: str = "music_wire",
        max_outer_diameter: float | None = None,
        index_range: Sequence[float] | None = None,
        own_mass: bool = True,
        stress_reserve: float = STRESS_RESERVE,
        duty: Duty | dict | None = None,
        ideal: bool = False,
        **kwargs: Any,
    ):
        label = f"{type(self).__name__} {name or ''}".strip()
        #: what the coil must survive (fatigue is then a rule at every sample), or None
        self.duty = _duty(duty, self.helical_kind, label)
        if ideal:
            raise InputError(
                f"{label}: a helical spring is not ideal; write ideal: true on a spring without coil "
                "parameters for the ideal law"
            )
        if "mass" in kwargs:
            raise InputError(f"{label}: a helical spring's mass follows from its coil; own_mass: false leaves it out")
        self.material = material_named(material)
        self.index_range = _index_range(index_range, label)
        reserve = float(stress_reserve) if not isinstance(stress_reserve, bool) else float("nan")
        if not 0 <= reserve < 1:
            raise InputError(f"{label}: stress_reserve must lie in [0, 1), got {stress_reserve!r}")
        #: fraction of every allowable stress the optimisation keeps in reserve [1]
        self.stress_reserve = reserve
        self.max_outer_diameter = None
        low_d, high_d = self.material.diameter_range
        if max_outer_diameter is not None:
            envelope = float(max_outer_diameter)
            if not (np.isfinite(envelope) and envelope > 0):
                raise InputError(
                    f"{label}: max_outer_diameter must be a positive number [m], got {max_outer_diameter!r}"
                )
            smallest = low_d * (self.index_range[0] + 1)  # D + d of the thinnest wire [m]
            if smallest > envelope:
                raise InputError(
                    f"{label}: max_outer_diameter {envelope * 1e3:g} mm is smaller than any coil of "
                    f"{self.material.label} (thinnest wire {low_d * 1e3:g} mm at index "
                    f"{self.index_range[0]:g}: {smallest * 1e3:.3g} mm outside)"
                )
            self.max_outer_diameter = envelope
            high_d = min(high_d, envelope / (self.index_range[0] + 1))
        kwargs.setdefault("wire_diameter", Free(low_d, high_d))
        kwargs.setdefault(
            "mean_diameter",
            Free(self.index_range[0] * low_d, min(self.index_range[1] * high_d, self.max_outer_diameter or np.inf)),
        )
        for key, (lower, upper) in self.default_bounds.items():
            kwargs.setdefault(key, Free(lower, upper))
        self.own_mass = bool(own_mass)
        super().__init__(a, b, name, **kwargs)
        self._check_wire_range(label)

    def _check_wire_range(self, label: str) -> None:
        """InputError when the bounds of ``wire_diameter`` leave the material's range."""
        wire = self.parameters["wire_diameter"]
        lowest, highest = (float(wire.lower), float(wire.upper)) if isinstance(wire, Free) else (float(wire),) * 2
        if lowest < self.material.diameter_range[0] * (1 - 1e-9) or highest > self.material.diameter_range[1] * (
            1 + 1e-9
        ):
            raise InputError(
                f"{label}: wire_diameter [{lowest * 1e3:g}, {highest * 1e3:g}] mm leaves the range of "
                f"{self.material.label}, {self.material.diameter_range[0] * 1e3:g}–"
                f"{self.material.diameter_range[1] * 1e3:g} mm"
            )

    # ---------------------------------------------------------------- the coil
    def rate(self, values: Mapping[str, ValueT]) -> ValueT:
        """``k = G d⁴ / (8 D³ n)`` [N/m] (numbers or CasADi)."""
        d, D, n = values["wire_diameter"], values["mean_diameter"], values["active_coils"]
        return self.material.shear_modulus * d**4 / (8 * D**3 * n)

    def coil_mass(self, values: Mapping[str, ValueT]) -> ValueT:
        """``ρ (π d²/4) π D (n + 2)`` [kg]."""
        d, D, n = values["wire_diameter"], values["mean_diameter"], values["active_coils"]
        return self.material.density * (math.pi * d**2 / 4) * math.pi * D * (n + 2)

    def body_stress(self, force: ValueT, values: Mapping[str, ValueT]) -> ValueT:
        """Bergsträsser-corrected shear stress ``K_B 8 |F| D / (π d³)`` [Pa] under force ``F`` [N]."""
        d, D = values["wire_diameter"], values["mean_diameter"]
        return bergstrasser_factor(D / d) * 8 * force * D / (math.pi * d**3)

    @property
    def winds(self) -> bool:
        """True for a coil to be wound (the winding rules apply: index range, initial tension band);
        False for a stock part (``part_number``), which exists already: only the rules of its use apply."""
        return self.part_number is None

    def common_rows(self, values: Parameters) -> list:
        """Index within its range (a coil to be wound) and the outer diameter within the envelope (rows ≥ 0)."""
        index = values["mean_diameter"] / values["wire_diameter"]
        rows = [index - self.index_range[0], self.index_range[1] - index] if self.winds else []
        if self.max_outer_diameter is not None:
            rows.append(self.max_outer_diameter - (values["mean_diameter"] + values["wire_diameter"]))
        return rows

    def fatigue_constraints(self) -> list:
        """The fatigue rows (:class:`~springbalance.springs.fatigue_rows.FatigueRules`) when the coil has a duty and
        something to design (a free parameter or anchor); a coil fixed in place has nothing they could steer, and
        its spec sheet judges its fatigue from the force range."""
        if self.duty is None:
            return []
        free = any(isinstance(value, Free) and value.upper > value.lower for value in self.parameters.values())
        try:
            free = free or any(anchor.is_free for anchor in self.anchors.values())
        except InputError:  # an anchor on a collision surface: its region follows from the arm
            free = True
        return [FatigueRules(self, self.duty)] if free else []

    def common_parts(self) -> list:
        parts = [("index_low", "1", 1.0), ("index_high", "1", 1.0)] if self.winds else []
        if self.max_outer_diameter is not None:
            parts.append(("outer_diameter", "m", 0.001))
        return parts

    # ---------------------------------------------------------------- its own mass
    @property
    def carries_mass(self) -> bool:
        return self.own_mass

    def spring_mass(self, parameters: Parameters) -> Value:
        return self.coil_mass(parameters) if self.own_mass else 0.0

    def part_mass(self, parameters: Parameters) -> Value:
        """The coil's mass [kg], also with ``own_mass: false`` (which only leaves its weight out of the model)."""
        return self.coil_mass(parameters)

    @property
    def mass(self) -> str | None:
        """``"coil"`` when the coil carries its own mass (computed from the geometry), else None."""
        return "coil" if self.own_mass else None

    @mass.setter
    def mass(self, value: Any) -> None:  # TwoPointSpring sets None: the mass follows from the coil instead
        self._mass = None

    def options(self) -> dict:
        record = super().options()
        record.update(
            {
                "material": self.material.name,
                "own_mass": self.own_mass,
                "index_range": list(self.index_range),
                "stress_reserve": self.stress_reserve,
            }
        )
        if self.max_outer_diameter is not None:
            record["max_outer_diameter"] = self.max_outer_diameter
        if self.duty is not None:
            record["duty"] = self.duty.to_dict()
        return record

    # ---------------------------------------------------------------- the data sheet
    def common_sheet(self, values: dict, largest: float) -> tuple[dict, list[str]]:
        """The entries and failed rules every coil shares, at the largest force ``largest`` [N]."""
        d, D, n = float(values["wire_diameter"]), float(values["mean_diameter"]), float(values["active_coils"])
        index = D / d
        strength = float(self.material.tensile_strength(d))  # [Pa]
        allowable = self.material.allowable_fraction[self.helical_kind] * strength
        stress = float(self.body_stress(largest, values))
        slack = 1 + CHECK_TOLERANCE
        reasons = []
        if stress > allowable * slack:
            reasons.append(f"body stress {stress / MPA:.0f} MPa exceeds the allowable {allowable / MPA:.0f} MPa")
        if self.winds and not self.index_range[0] / slack <= index <= self.index_range[1] * slack:
            reasons.append(f"index D/d = {index:.2f} outside {self.index_range[0]:g}–{self.index_range[1]:g}")
        if self.max_outer_diameter is not None and D + d > self.max_outer_diameter * slack:
            reasons.append(
                f"outer diameter {(D + d) * 1e3:.2f} mm exceeds the envelope {self.max_outer_diameter * 1e3:.2f} mm"
            )
        low_d, high_d = self.material.diameter_range
        if not low_d / slack <= d <= high_d * slack:
            reasons.append(f"wire {d * 1e3:.3g} mm outside the material's range {low_d * 1e3:g}–{high_d * 1e3:g} mm")
        if n < 1:
            reasons.append(f"{n:.3g} active coils: fewer than one")
        sheet = {
            "type": f"helical {self.helical_kind}",
            "material": self.material.name,
            "end_type": self.end_type,
            **({"part_number": self.part_number} if self.part_number is not None else {}),
            "wire_diameter": d,
            "mean_diameter": D,
            "outer_diameter": D + d,
            "index": index,
            "active_coils": n,
            "rate": float(self.rate(values)),
            "max_load": largest,
            "max_stress": stress,
            "allowable_stress": allowable,
            "mass": float(self.coil_mass(values)),
        }
        return sheet, reasons

    def fatigue_sheet(self, sheet: dict, forces: np.ndarray, reasons: list[str]) -> None:
        """Add ``duty`` and ``fatigue`` (per location: ``n_f``, the life it allows, the data) to ``sheet`` from the
        force range over ``forces`` [N]. With a stated duty, a location below its ``n_f`` is a reason the coil is
        not buildable; without one the coil is judged at the default :class:`~springbalance.springs.fatigue.Duty`
        (``duty.stated`` false) and a shortfall is only reported (the ``short_life`` warning)."""
        duty = self.duty if self.duty is not None else Duty()
        low, high = force_range(forces, self.helical_kind)
        margins = fatigue_margins(
            sheet["wire_diameter"], sheet["mean_diameter"], self.material, low, high, duty, self.helical_kind
        )
        sheet["duty"] = {**duty.to_dict(), "stated": self.duty is not None}
        sheet["fatigue"] = {"min_load": low, "max_load": high, **{key: m.to_dict() for key, m in margins.items()}}
        if self.duty is None:
            return
        for location, margin in margins.items():
            if margin.safety_factor < margin.required * (1 - CHECK_TOLERANCE):
                reasons.append(
                    f"fatigue at the {location.replace('_', ' ')}: n_f = {margin.safety_factor:.2f} below "
                    f"{margin.required:g} for {sheet['duty']['cycles']} cycles ({margin.source}); it lives "
                    f"{margin.life_text()}"
                )


def _duty(record: Duty | dict | None, kind: str, label: str) -> Duty | None:
    """The coil's :class:`~springbalance.springs.fatigue.Duty` (None without one); InputError naming the key."""
    return None if record is None else duty_from_record(record, f"{label}: duty").check_kind(kind, f"{label}: duty")


def _index_range(value: Any, label: str) -> tuple[float, float]:
    if value is None:
        return 4.0, 12.0
    try:
        low, high = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"{label}: index_range must be [low, high], got {value!r}") from None
    if not (3 <= low <= high):
        raise InputError(f"{label}: index_range must satisfy 3 ≤ low ≤ high, got {value!r}")
    return low, high
