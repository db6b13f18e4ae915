"""The duty an order states: how many load cycles the spring must live, whether it is shot-peened, and the
fatigue safety factor and life per location.

A gravity balancer's spring is preloaded and cycles between its working loads ``F1`` and ``F2`` every time
the arm moves, so a spring maker asks for the number of cycles and the surface treatment (DIN 2099-1/-2,
"type of loading"). :func:`coil_duty` takes the coil's ``duty`` record (:class:`springbalance.springs.fatigue.Duty`)
when it has one, else the default duty (10⁶ cycles, not peened, docs/model.md §3.8.2) marked as assumed, and
computes the fatigue margin of every location (body; hook bending and hook torsion of an extension spring)
for the force range ``F1`` … ``F2`` with :func:`springbalance.springs.fatigue.fatigue_margins`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from springbalance.springs.fatigue import Duty, Margin, fatigue_margins
from springbalance.springs.laws.coil import HelicalCoilSpring


@dataclasses.dataclass(frozen=True)
class OrderDuty:
    """What the order says about the spring's duty.

    Attributes:
        duty: the duty (cycles, peening, reliability, required n_f, criterion).
        assumed: True when the design gives no duty and the default one is stated instead.
        margins: location → its fatigue margin at the force range of the order (n_f, the life it allows).
    """

    duty: Duty
    assumed: bool
    margins: dict[str, Margin]

    @property
    def cycles_text(self) -> str:
        """The cycles as the form shows them: ``1e+06`` or ``infinite``."""
        return "infinite" if math.isinf(self.duty.cycles) else f"{self.duty.cycles:.3g}"

    @property
    def note(self) -> str:
        """Where the duty comes from."""
        if self.assumed:
            return (
                "the design gives no duty: the default duty of docs/model.md §3.8.2 is stated (an arm that moves "
                "every 10 s, 8 h a day, 250 days a year cycles its springs 7·10⁵ times a year); change it in the "
                "design's coil record (duty) if the arm works otherwise"
            )
        return "the design's duty (its coil's duty record)"

    def to_dict(self) -> dict[str, Any]:
        """The record of ``order.json``."""
        return {
            **self.duty.to_dict(),
            "assumed": self.assumed,
            "margins": {location: margin.to_dict() for location, margin in self.margins.items()},
        }


def coil_duty(
    spring: HelicalCoilSpring, wire_diameter: float, mean_diameter: float, min_force: float, max_force: float
) -> OrderDuty:
    """The duty of the coil ``spring`` of wire ``wire_diameter`` and mean coil diameter ``mean_diameter`` [m]
    (its ``duty`` record, or the default, assumed) and its fatigue margins for a force magnitude cycling
    between ``min_force`` and ``max_force`` [N] (clipped at 0: a coil that goes slack cycles from 0)."""
    record = getattr(spring, "duty", None)
    duty = record if isinstance(record, Duty) else Duty()
    low = max(min(min_force, max_force), 0.0)
    high = max(max_force, min_force, 0.0)
    # its record as a mapping: fatigue_margins reads a mapping (it calls dict() on what it is given)
    margins = fatigue_margins(
        wire_diameter, mean_diameter, spring.material, low, high, duty.to_dict(), spring.helical_kind
    )
    return OrderDuty(duty, not isinstance(record, Duty), margins)
