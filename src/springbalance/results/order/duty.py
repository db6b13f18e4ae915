"""The duty an order states: how many load cycles the spring must live, whether it is shot-peened, and the
fatigue safety factor per location (the seam to the fatigue check).

A gravity balancer's spring is preloaded and cycles between its working loads ``F1`` and ``F2`` every
time the arm moves, so a spring maker asks for the number of cycles and the surface treatment
(DIN 2099-1/-2, "type of loading"). The fatigue check of issue 28 (part 2) gives every coil a ``duty``
record (``cycles``, ``peened``, ``reliability``) and its spec sheet the fatigue safety factor ``n_f`` per
location (body; hook bending and hook torsion for extension springs). :func:`coil_duty` reads them
where they are; on a coil without them it returns a :class:`Duty` whose ``missing`` says that the design
was checked against the static rules only, and the order prints that instead of a number of cycles.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping

#: the spec-sheet entries of the fatigue check: location → key of its safety factor n_f
FATIGUE_KEYS = {
    "body": "body_fatigue_factor",
    "hook bending": "hook_bending_fatigue_factor",
    "hook torsion": "hook_torsion_fatigue_factor",
}


@dataclasses.dataclass(frozen=True)
class Duty:
    """What the order says about the spring's duty (None: not given, see ``missing``).

    Attributes:
        cycles: the load cycles it must live [1].
        peened: whether it is shot-peened.
        reliability: the reliability the fatigue check used [1].
        safety_factors: location → fatigue safety factor n_f [1] (empty when not checked).
        missing: why the duty is not given ("" when it is).
    """

    cycles: float | None = None
    peened: bool | None = None
    reliability: float | None = None
    safety_factors: dict[str, float] = dataclasses.field(default_factory=dict)
    missing: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The record of ``order.json``."""
        return dataclasses.asdict(self)


def _entry(record: Any, key: str) -> Any:
    """``record[key]`` of a mapping, or its attribute ``key``; None when it has neither."""
    if isinstance(record, Mapping):
        return record.get(key)
    return getattr(record, key, None)


def coil_duty(spring: Any, sheet: Mapping[str, Any]) -> Duty:
    """The duty of the coil ``spring`` (its ``duty`` record, when it has one) and the fatigue safety factors
    of its spec sheet ``sheet`` (:meth:`~springbalance.springs.laws.helical_extension.HelicalExtensionSpring.spec_sheet`)."""
    record = getattr(spring, "duty", None)
    factors = {location: float(sheet[key]) for location, key in FATIGUE_KEYS.items() if key in sheet}
    if record is None:
        return Duty(
            safety_factors=factors,
            missing="the design gives no duty: it was checked against the static rules only (no fatigue "
            "check); state the load cycles the spring must live before ordering it for a moving arm",
        )
    cycles, peened, reliability = (_entry(record, key) for key in ("cycles", "peened", "reliability"))
    return Duty(
        cycles=None if cycles is None else float(cycles),
        peened=None if peened is None else bool(peened),
        reliability=None if reliability is None else float(reliability),
        safety_factors=factors,
    )
