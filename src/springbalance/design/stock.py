r"""Stock springs: replace designed coil springs by catalogue parts and re-optimise the anchors.

A continuous design picks any rate ``k``, free length ``l0`` and preload ``F0``; a real arm is
usually built from springs one can buy. :func:`select_stock` turns a continuous optimum into a
stock design, greedily, spring by spring (in the problem's order):

1. for a spring of type ``extension`` or ``compression`` (:class:`ExtensionSpring`,
   :class:`CompressionSpring`, or a helical coil law of those types; gas springs, torsional and
   other laws keep their continuous design, and so does a spring that already has a
   ``part_number``), rank the catalogue's parts of
   that type by :func:`part_distance`: how alike they pull over the spring's working lengths at
   the current optimum, and whether they carry its load and stroke;
2. for each of the ``candidates`` nearest parts, replace the spring by the fixed spring of that
   part (:func:`part_spring`: rate, free length, preload and load/length limits of the part;
   the anchors stay free) and re-optimise: a new :class:`DesignProblem` with the same mechanism,
   workspace, objective, weights and scenarios, every free variable warm-started at the current
   optimum (``Free(lower, upper, init=...)``);
3. keep the candidate with the lowest objective among the feasible ones, and go on to the next
   spring from its optimum. When no candidate is feasible, :class:`SolverError` names the spring.

The result is a :class:`StockSelection`: the final design and what the choice cost (the
objective of the continuous design against the stock design, and every candidate tried).

The parts are :class:`StockPart` records; :func:`springbalance.io.catalogue.read_catalogue`
reads them from a CSV file (docs/guides/coils-and-stock.md, "Stock springs").
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import numpy.typing as npt

from springbalance.design.problem import DesignProblem
from springbalance.errors import InputError
from springbalance.springs.laws import Spring, TwoPointSpring
from springbalance.springs.laws.helical_compression import HelicalCompressionSpring
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
from springbalance.springs.params import Free, Plane, Segment
from springbalance.springs.records import spring_from_dict
from springbalance.springs.sizing import MATERIALS

#: the spring types a catalogue part can be (the ``type`` column of a catalogue).
STOCK_KINDS = ("extension", "compression")
#: parts tried per spring by default.
CANDIDATES = 6


@dataclasses.dataclass(frozen=True)
class StockPart:
    """One catalogue spring (SI units: m, N, N/m).

    Attributes:
        part_number: the catalogue's name of the part.
        kind: ``"extension"`` or ``"compression"`` (the ``type`` column).
        material: a key of :data:`springbalance.springs.sizing.MATERIALS`.
        wire_diameter: ``d`` [m].
        mean_diameter: mean coil diameter ``D`` [m].
        active_coils: ``n`` [1].
        free_length: ``l0`` [m] (extension: hooks included).
        initial_tension: ``F_i`` [N] (extension; 0 for compression springs).
        rate: ``k`` [N/m], ``G d⁴/(8 D³ n)``.
        max_load: largest force [N].
        max_length: extension: the longest allowed length; compression: the free length [m].
        min_length: extension: the free length; compression: the solid length [m].
    """

    part_number: str
    kind: str
    material: str
    wire_diameter: float
    mean_diameter: float
    active_coils: float
    free_length: float
    initial_tension: float
    rate: float
    max_load: float
    max_length: float
    min_length: float

    @property
    def index(self) -> float:
        """Spring index ``C = D/d`` [1]."""
        return self.mean_diameter / self.wire_diameter

    @property
    def mass(self) -> float:
        """Mass of the wire [kg]: ``ρ (π d²/4) π D (n + 2)`` (two hooks, or two closed end coils)."""
        density = MATERIALS[self.material].density if self.material in MATERIALS else float("nan")
        wire_length = math.pi * self.mean_diameter * (self.active_coils + 2.0)
        return density * wire_length * math.pi * self.wire_diameter**2 / 4

    def to_dict(self) -> dict[str, Any]:
        """The catalogue row as a mapping (``type`` for :attr:`kind`)."""
        record = dataclasses.asdict(self)
        record["type"] = record.pop("kind")
        return record

    def describe(self) -> str:
        """One line: part number, rate, free length, preload, limits."""
        text = (
            f"{self.part_number} ({self.kind}, {self.material}, d {self.wire_diameter * 1e3:g} mm, "
            f"D {self.mean_diameter * 1e3:g} mm, n {self.active_coils:g}): k {self.rate:.4g} N/m, "
            f"l0 {self.free_length * 1e3:.4g} mm"
        )
        if self.kind == "extension":
            return text + (
                f", F0 {self.initial_tension:.4g} N, max load {self.max_load:.4g} N, "
                f"max length {self.max_length * 1e3:.4g} mm"
            )
        return text + f", max load {self.max_load:.4g} N, solid length {self.min_length * 1e3:.4g} mm"


# ---------------------------------------------------------------------- one part as a spring
def stock_kind(spring: Spring) -> str | None:
    """``"extension"`` or ``"compression"`` when a catalogue part can replace ``spring`` (a two-point
    spring of that type: the ideal law or a helical coil), else None (gas springs, every other law)."""
    if isinstance(spring, TwoPointSpring) and spring.kind in STOCK_KINDS:
        return spring.kind
    return None


def part_spring(part: StockPart, spring: Spring) -> Spring:
    """The fixed helical coil of catalogue ``part`` in the place of ``spring`` (same name and anchors,
    which stay free when they are).

    Extension part: ``HelicalExtensionSpring`` with the part's wire, coil diameter, coils and initial
    tension (so its rate and free length are the part's), ``max_force=max_load``, ``max_length``,
    ``keep_tension=True``; compression part: ``HelicalCompressionSpring`` with its wire, coil
    diameter, coils and free length, ``stays_compressed=True``, ``max_force=max_load``. Either carries
    its ``part_number``, its own mass, and a spec sheet in every report; as a stock part the winding
    rules (index range, initial-tension band) do not apply, the rules of its use (stresses, hooks,
    solid length, buckling unless the spring was ``guided``) do. The spring's own limits stay when they
    are stricter (``max_force``, ``max_length``, ``min_length``: space or load limits of the arm), and
    so does its envelope (``max_outer_diameter``) and its ``duty`` (fatigue rows while the anchors are free).
    """
    kind = stock_kind(spring)
    if kind is None or not isinstance(spring, TwoPointSpring):  # (a stock kind is a two-point spring's)
        raise InputError(
            f"spring {spring.name!r} ({spring.kind}) cannot be a catalogue part; only extension and "
            "compression springs can"
        )
    if part.kind != kind:
        raise InputError(
            f"part {part.part_number!r} is a {part.kind} spring; spring {spring.name!r} is a {kind} spring"
        )
    max_force = part.max_load if spring.max_force is None else min(part.max_load, spring.max_force)
    coil = {
        "material": part.material,
        "wire_diameter": part.wire_diameter,
        "mean_diameter": part.mean_diameter,
        "active_coils": part.active_coils,
        "max_force": max_force,
        "min_length": spring.min_length,
        "max_outer_diameter": getattr(spring, "max_outer_diameter", None),
        "part_number": part.part_number,
        "duty": getattr(spring, "duty", None),
    }
    if getattr(spring, "routed", False):  # the part on the same path, with the same cable
        coil.update(via=spring.via, cable_length=spring.parameters["cable_length"])
    if kind == "extension":
        max_length = part.max_length if spring.max_length is None else min(part.max_length, spring.max_length)
        return HelicalExtensionSpring(
            spring.a,
            spring.b,
            spring.name,
            initial_tension=part.initial_tension,
            max_length=max_length,
            keep_tension=True,
            **coil,
        )
    return HelicalCompressionSpring(
        spring.a,
        spring.b,
        spring.name,
        free_length=part.free_length,
        max_length=spring.max_length,
        stays_compressed=True,
        guided=bool(getattr(spring, "guided", False)),
        **coil,
    )


def part_distance(part: StockPart, lengths: npt.ArrayLike, forces: npt.ArrayLike) -> float:
    r"""How far ``part`` is from a designed spring that has ``lengths`` [m] and tensions ``forces``
    [N] (negative: pushing) at the workspace samples; dimensionless, 0 for the same spring.

    .. math::
        \delta^2 = \operatorname{mean}_i \Bigl(\frac{F_p(L_i) - F_i}{F_{max}}\Bigr)^2
                 + \max\Bigl(0, \ln\frac{F_{max}}{F_{p,max}}\Bigr)^2
                 + \max\Bigl(0, \ln\frac{L_{max} - L_{min}}{s_p}\Bigr)^2

    The first term compares the rate, free length and preload where they act: the part's force
    ``F_p(L) = F_0 + k (L - l_0)`` (extension; ``-k (l_0 - L)`` compression) against the designed
    spring's force at its working lengths, relative to the largest designed force ``F_max``. So a
    part counts as near when it pulls (or pushes) alike over the working range: its rate, free
    length and preload count together, by the force they make, not one by one. The other two
    terms are zero for a part that can do the designed spring's job: they grow when the part's
    ``max_load`` is below ``F_max``, and when its stroke ``s_p`` (extension: ``max_length - l0``;
    compression: ``l0`` minus the solid length) is shorter than the designed spring's working
    stroke ``L_max - L_min``. Re-optimising the anchors changes lengths and forces, so the
    distance only ranks the candidates; the objective after re-optimising picks among them.
    """
    lengths = np.asarray(lengths, dtype=float)
    forces = np.asarray(forces, dtype=float)
    scale = max(float(np.max(np.abs(forces))), 1e-9)  # F_max [N]
    if part.kind == "extension":
        part_forces = part.initial_tension + part.rate * (lengths - part.free_length)
        stroke = part.max_length - part.free_length
    else:
        part_forces = -part.rate * (part.free_length - lengths)
        stroke = part.free_length - part.min_length
    line = float(np.mean(((part_forces - forces) / scale) ** 2))
    load = max(0.0, math.log(scale / part.max_load))
    needed = float(np.max(lengths) - np.min(lengths))
    reach = max(0.0, math.log(needed / stroke)) if needed > 0 else 0.0
    return math.sqrt(line + load * load + reach * reach)


# ---------------------------------------------------------------------- the record of a selection
@dataclasses.dataclass
class StockTrial:
    """One candidate part for one spring: its distance, and the objective after re-optimising
    (``None`` when no start was feasible; ``status`` says why)."""

    part: StockPart
    distance: float
    objective: float | None
    status: str

    def to_dict(self) -> dict[str, Any]:
        return {
            "part_number": self.part.part_number,
            "distance": self.distance,
            "objective": self.objective,
            "status": self.status,
        }


@dataclasses.dataclass
class StockChoice:
    """The part chosen for one spring.

    Attributes:
        spring: the spring's name; ``kind``: its type.
        designed: its parameter values before the choice (an ideal spring's ``stiffness``,
            ``free_length``, and ``initial_tension`` or ``preload``; a coil's wire and coils), and
            over the workspace its shortest and longest length ``min_length``, ``max_length`` [m],
            its smallest and largest tension ``min_force``, ``max_force`` [N] (negative: pushing).
        part: the chosen part.
        objective: the objective after this choice (anchors and the springs not yet chosen re-optimised).
        trials: every candidate tried, nearest first.
    """

    spring: str
    kind: str
    designed: dict
    part: StockPart
    objective: float
    trials: list
    #: a :class:`~springbalance.design.stock_checks.PartFatigue` once checked (typed loosely: that module
    #: imports the tolerance analysis, which imports the evaluated design, which imports these records)
    fatigue: Any = None
    tolerance: dict | None = None

    def to_dict(self) -> dict[str, Any]:
        return {
            "spring": self.spring,
            "type": self.kind,
            "designed": dict(self.designed),
            "part": self.part.to_dict(),
            "objective": self.objective,
            "trials": [trial.to_dict() for trial in self.trials],
            "fatigue": None if self.fatigue is None else self.fatigue.to_dict(),
            "tolerance": self.tolerance,
        }

    def check_lines(self) -> list[str]:
        """The part's fatigue and tolerance, one line each (none before they are checked)."""
        lines = [] if self.fatigue is None else [self.fatigue.line()]
        if self.tolerance is not None:
            box, travel = self.tolerance["box"], self.tolerance["travel"]
            lines.append(
                f"tolerance {box['source']}: k ± {100 * box['rate']:.3g} %, F0 ± {box['initial_tension']:.3g} N, "
                f"l0 ± {box['free_length'] * 1e3:.3g} mm; preload-screw travel {travel * 1e3:.3g} mm restores the balance"
            )
        return lines


@dataclasses.dataclass
class StockSelection:
    """What :func:`select_stock` did.

    Attributes:
        result: the stock design (a :class:`~springbalance.results.result.DesignResult` of the final
            problem, whose stock springs carry their ``part_number``).
        objective: the objective's name; ``unit`` its unit.
        continuous_objective: the objective of the continuous design.
        stock_objective: the objective of the stock design (same objective, workspace and weights).
        choices: one :class:`StockChoice` per replaced spring, in the order they were chosen.
        notes: anything the selection changed besides the springs (per-scenario variables dropped).
        tolerance: the stock design's worst residual over its springs' tolerance boxes, and the adjuster
            travel (:mod:`springbalance.design.stock_checks`).
    """

    result: Any
    objective: str
    unit: str
    continuous_objective: float
    stock_objective: float
    choices: list
    notes: list = dataclasses.field(default_factory=list)
    tolerance: Any = None  # a springbalance.design.tolerance.ToleranceAnalysis once checked

    @property
    def cost(self) -> float:
        """What the stock choice cost: stock objective − continuous objective (objective unit)."""
        return self.stock_objective - self.continuous_objective

    @property
    def cost_percent(self) -> float:
        """:attr:`cost` relative to the continuous objective [%]; NaN when that is 0 or negligible
        (below 1e-6 of the stock objective: an exact continuous balance)."""
        if not self.continuous_objective > 1e-6 * abs(self.stock_objective):
            return float("nan")
        return 100.0 * self.cost / self.continuous_objective

    def parts(self) -> dict[str, str]:
        """Spring name → part number."""
        return {choice.spring: choice.part.part_number for choice in self.choices}

    def summary(self) -> str:
        """Plain text: the part of each spring (designed values → part) and the objective before and after."""
        lines = ["Stock springs (nearest catalogue parts, anchors re-optimised)"]
        for choice in self.choices:
            designed = choice.designed
            preload_key = "initial_tension" if choice.kind == "extension" else "preload"
            feasible = sum(trial.objective is not None for trial in choice.trials)
            values = (
                f"k {designed['stiffness']:.4g} N/m, l0 {designed['free_length'] * 1e3:.4g} mm, "
                f"F0 {designed.get(preload_key, 0.0):.4g} N, "
                if "stiffness" in designed
                else ""
            )
            lines.append(
                f"  {choice.spring} ({choice.kind}): designed {values}tension {designed['min_force']:.4g} … "
                f"{designed['max_force']:.4g} N over {designed['min_length'] * 1e3:.4g} … "
                f"{designed['max_length'] * 1e3:.4g} mm"
            )
            lines.append(f"    → {choice.part.describe()}")
            lines += [f"    {line}" for line in choice.check_lines()]
            lines.append(
                f"    {feasible} of {len(choice.trials)} candidates feasible; {self.objective} after this "
                f"choice {choice.objective:.6g} {self.unit}"
            )
        change = self.cost_percent
        relative = "" if not np.isfinite(change) else f" ({change:+.1f} %)"
        lines.append(
            f"  objective {self.objective}: continuous {self.continuous_objective:.6g} {self.unit} → "
            f"stock {self.stock_objective:.6g} {self.unit}{relative}"
        )
        for joint in [] if self.tolerance is None else self.tolerance.joints:
            lines.append(
                f"  worst over the tolerance boxes, {joint['joint']}: peak {joint['worst_peak']:.4g} {joint['unit']} "
                f"(nominal {joint['peak']:.4g}), {joint['adjusted_peak']:.4g} after the adjusters"
            )
        lines += [f"  note: {note}" for note in self.notes]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        return {
            "objective": self.objective,
            "unit": self.unit,
            "continuous_objective": self.continuous_objective,
            "stock_objective": self.stock_objective,
            "cost": self.cost,
            "parts": self.parts(),
            "choices": [choice.to_dict() for choice in self.choices],
            "notes": list(self.notes),
            "tolerance": None if self.tolerance is None else self.tolerance.to_dict(),
        }


def warm_started(problem: DesignProblem, x: np.ndarray) -> list[Spring]:
    """The problem's springs with every free variable's ``init`` at its value in design ``x``
    (the first scenario's value for a per-scenario variable): the same bounds, a warm start."""
    base = problem.model.scenario_vector(x, 0)
    names = problem.model.base_variables.names
    springs = []
    for spring in problem.springs:
        record = spring.to_dict()
        values = problem.model.spring_values(spring, x)
        for key, value in spring.parameters.items():
            if isinstance(value, Free) and value.upper > value.lower:
                record[key]["init"] = float(np.clip(values[key], value.lower, value.upper))
        for end, anchor in spring.anchors.items():
            region = anchor.region()
            if not region.labels:
                continue
            coordinates = np.array([base[names.index(f"{spring.name}.{end}.{label}")] for label in region.labels])
            point = anchor.point
            if isinstance(point, Free):  # a box: init is the whole point
                init = np.clip(region.point(coordinates), point.lower, point.upper).tolist()
                record[end]["box"]["init"] = init
            elif isinstance(point, Segment):
                record[end]["segment"]["init"] = float(np.clip(coordinates[0], region.lower[0], region.upper[0]))
            elif isinstance(point, Plane):
                record[end]["plane"]["init"] = np.clip(coordinates, region.lower, region.upper).tolist()
        springs.append(spring_from_dict(record, f"spring {spring.name!r}"))
    return springs
