r"""The fields of a DIN 2099 spring order, per helical spring of a design.

DIN 2099-1 (form A, cold-formed compression springs) and DIN 2099-2 (form B, cold-formed extension
springs) list what a spring maker needs to quote and make a spring: the wire (standard, grade, diameter
``d`` with its tolerance), the coil diameter that is controlled (outer ``De`` or inner ``Di``) with its
tolerance, the coil direction, the active and total coils (for reference: the maker adjusts them to hit
the loads), the free length ``L0``, two loads ``F1``, ``F2`` at the test lengths ``L1``, ``L2`` with
their tolerances, the initial tension ``F0`` and the loops (extension springs) or the ends (compression
springs), the quality grade, the duty and the finish.

The numbers come from the design (:class:`~springbalance.design.evaluated.EvaluatedDesign`): a coil's
values and spec sheet, and its length and force at every workspace sample. The two test states are the
working extremes over the workspace, state 1 the smaller load and state 2 the larger:

- extension spring (law :math:`F = F_0 + R\,(L - L_0)`): ``L1`` the shortest length, ``L2`` the longest;
- compression spring (:math:`F = R\,(L_0 - L)`, pushing): ``L1`` the longest length, ``L2`` the shortest.

A field the design cannot fill (a tolerance without its table, the finish, the duty of a design checked
statically only) has no value and a ``note`` that says why; nothing is left blank silently.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.results.order.duty import OrderDuty, coil_duty
from springbalance.results.order.tolerances import DEFAULT_GRADE, Tolerances, grade_tolerances
from springbalance.springs.helical_formulas import HOOK_SIDE_BEND_INDEX
from springbalance.springs.laws.coil import HelicalCoilSpring
from springbalance.springs.wire_standards import wire_grade, wire_standard, wire_tolerance

#: the DIN 2099 part (and its form) per spring kind
FORMS = {"extension": "DIN 2099-2 (form B)", "compression": "DIN 2099-1 (form A)"}


@dataclasses.dataclass(frozen=True)
class Field:
    """One field of the order form.

    Attributes:
        key: its name in ``order.json``.
        label: its name on the form, with its symbol.
        value: a number in SI units (m, N, N/m, 1), a text, or None (then ``note`` says why).
        unit: the SI unit of a number ("m", "N", "N/m", "1"), "" for a text.
        tolerance: ± in the unit of ``value`` (None: none applies, or see ``tolerance_note``).
        reference: the value is for reference only (not inspected; the maker may adjust it).
        note: the source of the value, or why it is missing.
        tolerance_note: the source of the tolerance, or why it is missing ("" when no tolerance applies).
    """

    key: str
    label: str
    value: float | str | None
    unit: str = ""
    tolerance: float | None = None
    reference: bool = False
    note: str = ""
    tolerance_note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The record of ``order.json``."""
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True)
class SpringOrder:
    """The order of one helical spring: its form's fields, its tolerances and duty, and the numbers the
    drawing needs (``geometry``: wire, diameters, coils, lengths [m]; ``loads``: ``(L [m], F [N])`` of the
    free state and the two test states)."""

    name: str
    kind: str
    form: str
    fields: tuple[Field, ...]
    tolerances: Tolerances
    duty: OrderDuty
    geometry: dict[str, float]
    loads: tuple[tuple[str, float, float], ...]

    def field(self, key: str) -> Field:
        """The field called ``key``."""
        for field in self.fields:
            if field.key == key:
                return field
        raise KeyError(key)

    def to_dict(self) -> dict[str, Any]:
        """The record of ``order.json``."""
        return {
            "name": self.name,
            "kind": self.kind,
            "form": self.form,
            "fields": [field.to_dict() for field in self.fields],
            "tolerances": self.tolerances.to_dict(),
            "duty": self.duty.to_dict(),
            "geometry": dict(self.geometry),
        }


@dataclasses.dataclass(frozen=True)
class OrderOptions:
    """What the design does not say and the order does: quality grade, finish, coil direction, quantity."""

    grade: int = DEFAULT_GRADE
    finish: str | None = None
    direction: str = "right-hand"
    quantity: int = 1


def working_states(kind: str, lengths: np.ndarray, forces: np.ndarray) -> tuple[tuple[float, float], ...]:
    """The two test states ``((L1, F1), (L2, F2))`` [m, N] of a coil from its lengths and tensions at every
    sample: the working extremes, state 1 with the smaller load (forces of compression springs as pushes)."""
    lengths, forces = np.asarray(lengths, dtype=float), np.asarray(forces, dtype=float)
    loads = forces if kind == "extension" else -forces
    shortest, longest = int(np.argmin(lengths)), int(np.argmax(lengths))
    first, second = (shortest, longest) if kind == "extension" else (longest, shortest)
    return (float(lengths[first]), float(loads[first])), (float(lengths[second]), float(loads[second]))


def spring_orders(result: EvaluatedDesign, options: OrderOptions | None = None) -> list[SpringOrder]:
    """The order of every helical coil spring of ``result`` (the other springs have nothing to quote;
    :func:`springbalance.results.order.bom.not_quotable` lists them)."""
    options = options or OrderOptions()
    orders = []
    evaluation = result.evaluation
    for column, (spring, record) in enumerate(zip(result.problem.springs, result.springs)):
        if isinstance(spring, HelicalCoilSpring) and "helical" in record:
            states = working_states(spring.helical_kind, evaluation.lengths[:, column], evaluation.tensions[:, column])
            orders.append(_spring_order(spring, record, states, options))
    return orders


def _spring_order(
    spring: HelicalCoilSpring, record: dict[str, Any], states: tuple[tuple[float, float], ...], options: OrderOptions
) -> SpringOrder:
    """The order of one coil from its design record (values and spec sheet) and its two test states."""
    sheet, kind = record["helical"], spring.helical_kind
    d, D, n = float(sheet["wire_diameter"]), float(sheet["mean_diameter"]), float(sheet["active_coils"])
    free, rate = float(sheet["free_length"]), float(sheet["rate"])
    initial = float(sheet.get("initial_tension", 0.0))
    (l1, f1), (l2, f2) = states
    tolerances = grade_tolerances(kind, options.grade, d, D, n, free, rate, initial, (f1, f2))
    duty = coil_duty(spring, d, D, f1, f2)
    total = n if kind == "extension" else n + 2
    geometry = {"wire_diameter": d, "mean_diameter": D, "active_coils": n, "total_coils": total, "free_length": free}
    geometry.update(body_length=float(sheet["body_length"]), rate=rate, initial_tension=initial)
    if kind == "compression":
        geometry["solid_length"] = float(sheet["solid_length"])
    fields = (
        _material_fields(spring, d)
        + _diameter_fields(spring, d, D, tolerances)
        + _coil_fields(kind, n, total, options)
        + _length_load_fields(kind, sheet, states, tolerances)
        + (_loop_fields(d, D) if kind == "extension" else _end_fields(spring, sheet))
        + _quality_fields(kind, tolerances, duty, options, record)
    )
    loads = (("free", free, initial if kind == "extension" else 0.0), ("1", l1, f1), ("2", l2, f2))
    return SpringOrder(str(spring.name), kind, FORMS[kind], fields, tolerances, duty, geometry, loads)


def _material_fields(spring: HelicalCoilSpring, d: float) -> tuple[Field, ...]:
    """Material standard and grade, wire diameter with its tolerance."""
    material = spring.material
    standard = wire_standard(material)
    plus_minus, source = wire_tolerance(material, d)
    return (
        Field(
            "material_standard",
            "Material standard",
            standard.name if standard else None,
            note=f"from the material {material.name!r}"
            if standard
            else f"no standard is known for {material.label}; name it",
        ),
        Field("material_grade", "Material grade", wire_grade(material), note=material.label),
        Field(
            "wire_diameter",
            "Wire diameter d",
            d,
            "m",
            plus_minus,
            note="the design's wire (a standard size when rounded)",
            tolerance_note=source,
        ),
    )


def _diameter_fields(spring: HelicalCoilSpring, d: float, D: float, tolerances: Tolerances) -> tuple[Field, ...]:
    """The controlled coil diameter with its tolerance (outer, unless a compression spring runs on a rod),
    and the other two for reference."""
    inner = bool(getattr(spring, "guided", False))
    envelope = spring.max_outer_diameter
    why = (
        "the spring runs on a rod (guided): its bore is what must fit"
        if inner
        else "the outer diameter is what must fit the space"
        + (f" (envelope {envelope * 1e3:g} mm)" if envelope is not None else "")
    )
    tolerance_note = tolerances.source if tolerances.coil_diameter is not None else tolerances.missing
    controlled = (
        ("inner_diameter", "Inner diameter Di", D - d) if inner else ("outer_diameter", "Outer diameter De", D + d)
    )
    other = ("outer_diameter", "Outer diameter De", D + d) if inner else ("inner_diameter", "Inner diameter Di", D - d)
    return (
        Field("controlled_diameter", "Controlled diameter", "inner (Di)" if inner else "outer (De)", note=why),
        Field(*controlled, "m", tolerances.coil_diameter, tolerance_note=tolerance_note),
        Field(*other, "m", reference=True, note="follows from the controlled diameter and d"),
        Field("mean_diameter", "Mean diameter D", D, "m", reference=True, note="the design's coil diameter"),
    )


def _coil_fields(kind: str, n: float, total: float, options: OrderOptions) -> tuple[Field, ...]:
    """Coil direction, active and total coils (reference: the maker adjusts them to meet the loads)."""
    ends = (
        "the close-wound body's coils N_b; the design takes every body coil as active (Shigley ch. 10 adds "
        "G/E ≈ 0.4 of a coil for the loops, which the maker's adjustment of n absorbs)"
        if kind == "extension"
        else "n + 2: one closed end coil at each end (squared and ground, Shigley Table 10-1)"
    )
    return (
        Field(
            "coil_direction",
            "Coil direction",
            options.direction,
            note="the balance does not depend on it; DIN 2099 takes right-hand unless the order says otherwise",
        ),
        Field("active_coils", "Active coils n", n, "1", reference=True, note="the maker adjusts n to meet the loads"),
        Field("total_coils", "Total coils nt", total, "1", reference=True, note=ends),
    )


def _length_load_fields(
    kind: str, sheet: dict[str, Any], states: tuple[tuple[float, float], ...], tolerances: Tolerances
) -> tuple[Field, ...]:
    """Free length, body or solid length, rate, initial tension, and the loads at the two test lengths."""
    missing = tolerances.missing
    where = "inside the loops" if kind == "extension" else "between the ground ends"
    fields = [
        Field(
            "free_length",
            "Free length L0",
            float(sheet["free_length"]),
            "m",
            reference=True,
            note=f"unloaded, {where}; for reference: with the two loads F1 at L1 and F2 at L2 specified, the "
            "maker adjusts L0 and n to meet them (DIN 2099-1/-2)",
        ),
    ]
    if kind == "extension":
        fields.append(
            Field("body_length", "Body length LK", float(sheet["body_length"]), "m", reference=True, note="d (n + 1)")
        )
        fields.append(
            Field(
                "initial_tension",
                "Initial tension F0",
                float(sheet["initial_tension"]),
                "N",
                tolerances.initial_tension,
                note="the force below which the coils stay closed",
                tolerance_note=tolerances.source if tolerances.initial_tension is not None else missing,
            )
        )
    else:
        fields.append(
            Field(
                "solid_length", "Solid length Lc", float(sheet["solid_length"]), "m", reference=True, note="d (n + 2)"
            )
        )
    fields.append(
        Field(
            "rate",
            "Spring rate R",
            float(sheet["rate"]),
            "N/m",
            tolerances.rate,
            reference=True,
            note="G d^4 / (8 D^3 n)",
            tolerance_note=tolerances.source if tolerances.rate is not None else missing,
        )
    )
    return tuple(fields) + _load_fields(kind, states, tolerances)


def _load_fields(kind: str, states: tuple[tuple[float, float], ...], tolerances: Tolerances) -> tuple[Field, ...]:
    """The test lengths ``L1``, ``L2`` and the loads ``F1``, ``F2`` there, with their tolerances."""
    fields = []
    missing = tolerances.missing
    extreme = ("shortest", "longest") if kind == "extension" else ("longest", "shortest")
    for index, (length, load), tolerance, word in zip((1, 2), states, tolerances.loads, extreme):
        fields.append(
            Field(f"length_{index}", f"Test length L{index}", length, "m", note=f"the {word} length over the workspace")
        )
        fields.append(
            Field(
                f"load_{index}",
                f"Load F{index} at L{index}",
                load,
                "N",
                tolerance,
                note=f"the spring's force at its {word} working length",
                tolerance_note=tolerances.source if tolerance is not None else missing,
            )
        )
    return tuple(fields)


def _loop_fields(d: float, D: float) -> tuple[Field, ...]:
    """Loop type and position of an extension spring (the design's ends: a machine loop each)."""
    return (
        Field(
            "loop_type",
            "Loop type",
            "full loop over the centre (machine loop) at both ends",
            note="the design's ends: L0 = LK + 2 (D - d), hook stresses checked at sections A and B (Shigley "
            "Eq. 10-34 to 10-36)",
        ),
        Field("loop_inside_diameter", "Loop inside diameter", D - d, "m", reference=True, note="D - d"),
        Field(
            "side_bend_radius",
            "Side-bend radius r2 (min)",
            HOOK_SIDE_BEND_INDEX * d / 2,
            "m",
            note=f"the hook torsion stress was checked at C2 = 2 r2/d = {HOOK_SIDE_BEND_INDEX:g}; a tighter bend "
            "stresses the hook more",
        ),
        Field(
            "loop_position",
            "Loop position",
            "in line (0°)",
            note="each loop hangs on a pin of its anchor, which takes any position; in line is the cheapest",
        ),
    )


def _end_fields(spring: HelicalCoilSpring, sheet: dict[str, Any]) -> tuple[Field, ...]:
    """End type of a compression spring, and whether it is guided."""
    guided = bool(getattr(spring, "guided", False))
    return (
        Field("end_type", "End type", f"closed and ground ({spring.end_type})", note="Shigley Table 10-1"),
        Field(
            "guide",
            "Guide",
            "on a rod or in a tube" if guided else "none",
            note="buckling not checked: guided"
            if guided
            else f"free length within the buckling limit {float(sheet['buckling_length']) * 1e3:.0f} mm",
        ),
    )


def _quality_fields(
    kind: str, tolerances: Tolerances, duty: OrderDuty, options: OrderOptions, record: dict[str, Any]
) -> tuple[Field, ...]:
    """Quality grade, duty (cycles, peening, fatigue factor and life per location), finish and quantity."""
    fields = [
        Field(
            "quality_grade",
            "Quality grade",
            f"{tolerances.standard} grade {tolerances.grade}",
            note="the tolerances of this grade apply to every toleranced value",
        ),
        Field(
            "cycles", "Load cycles", duty.cycles_text, note=f"between F1 and F2 at every move of the arm; {duty.note}"
        ),
        Field(
            "peening",
            "Shot peening",
            "peened" if duty.duty.peened else "not peened",
            note="a close-wound extension spring cannot be peened" if kind == "extension" else duty.note,
        ),
    ]
    for location, margin in duty.margins.items():
        factor = margin.safety_factor
        fields.append(
            Field(
                f"fatigue_{location}",
                f"Fatigue n_f ({location.replace('_', ' ')})",
                "infinite (no stress range)" if math.isinf(factor) else factor,
                "" if math.isinf(factor) else "1",
                reference=True,
                note=f"{duty.duty.criterion} on {margin.source}, required {margin.required:g}; "
                f"life at that factor: {margin.life_text()}",
            )
        )
    fields.append(
        Field(
            "finish",
            "Finish",
            options.finish,
            note="" if options.finish else "the design sets no finish; name one for the environment (--finish)",
        )
    )
    part = record.get("part_number") or record["helical"].get("part_number")
    fields.append(
        Field("quantity", "Quantity", float(options.quantity), "1", note=f"catalogue part {part}" if part else "")
    )
    return tuple(fields)
