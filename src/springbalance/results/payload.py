r"""Payload studies of a design: how far an adjustable anchor carries, and how a fixed design degrades.

- :func:`payload_range`: for a design whose problem has per-scenario variables (an
  adjustable anchor such as a slider on a link, a preload), keep the shared variables (the
  spring) at the design's values and re-fit only the per-scenario ones for each payload
  ``m`` [kg] at a point of a body. Returns the anchor position against the payload (a table
  and a plot) and the largest payload still balanced to a given peak residual torque,
  found by bracketing and, past the end of the travel, by the straight line that the
  residual follows there. For a single link with a zero-free-length spring (docs/model.md §9)
  the anchor moves by :math:`\Delta b = \Delta m\,w\,g/(k a)` and the largest payload for
  travel up to ``b_max`` is :math:`k a (b_{max} - b)/(w g)` (R4).
- :func:`residual_vs_payload`: one fixed design evaluated with each payload: peak and RMS
  residual torque against the payload.

Each payload is one scenario (:mod:`springbalance.design.scenarios`) on the bare mechanism; all
payloads of one sweep are solved at once as one stacked problem, whose per-scenario
variables are independent once the shared ones are fixed. Units: kg, m, N·m.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
import numpy.typing as npt

from springbalance.errors import InputError
from springbalance.design.problem import DesignProblem
from springbalance.design.scenarios import Payload, Scenario
from springbalance.design.solvers import refine
from springbalance.results.result import DesignResult
from springbalance.springs.records import spring_from_dict

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: the largest payload mass taken [kg] and the farthest payload point from its body's origin [m]:
#: beyond these a number is a typo, not a payload
MAX_MASS = 1e6
MAX_DISTANCE = 100.0

ANCHOR_COLOR = "#2b8cbe"
RESIDUAL_COLOR = "#d7301f"


@dataclasses.dataclass
class PayloadRow:
    """One payload: its mass [kg], per-scenario variable values, adjustable anchor points [m]
    (``"<spring>.<end>"`` → body-frame point), peak and RMS residual torque [N·m]."""

    mass: float
    variables: dict[str, float]
    anchors: dict[str, list[float]]
    peak: float
    rms: float
    balanced: bool

    def to_dict(self) -> dict[str, Any]:
        return {"mass": self.mass, "variables": self.variables,
                "anchors": {key: list(point) for key, point in self.anchors.items()},
                "peak": self.peak, "rms": self.rms, "balanced": self.balanced}


@dataclasses.dataclass
class PayloadRange:
    """Result of :func:`payload_range` (see there). ``max_payload`` [kg] is the largest payload
    whose peak residual stays ≤ ``max_residual`` [N·m] (``inf`` when none of the tried masses
    exceeded it)."""

    body: str
    point: tuple[float, ...]
    max_residual: float
    rows: list[PayloadRow]
    max_payload: float

    def table(self) -> str:
        anchors = list(self.rows[0].anchors) if self.rows else []
        header = f"  {'payload [kg]':>12s}" + "".join(f"{name + ' [m]':>28s}" for name in anchors) + \
                 f"{'peak [N·m]':>13s}{'rms [N·m]':>12s}  balanced"
        lines = [f"Payload range: payload at {list(self.point)} m of {self.body!r}, balanced when the peak "
                 f"residual ≤ {self.max_residual:.3g} N·m", header]
        for row in self.rows:
            points = "".join(f"{'[' + ', '.join(f'{v:+.4f}' for v in row.anchors[name]) + ']':>28s}" for name in anchors)
            lines.append(f"  {row.mass:12.4g}{points}{row.peak:13.4g}{row.rms:12.4g}  {'yes' if row.balanced else 'no'}")
        lines.append(f"  largest payload balanced: {self.max_payload:.6g} kg")
        return "\n".join(lines)

    def plot(self, path: str | Path | None = None) -> Figure:
        """matplotlib figure: adjustable anchor coordinates and peak residual against the payload
        (also saved as PNG and SVG when ``path`` is given)."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from springbalance.results.plots import save_figure

        rows = sorted(self.rows, key=lambda row: row.mass)
        masses = np.array([row.mass for row in rows])
        figure = Figure(figsize=(8.4, 3.2), layout="constrained")
        FigureCanvasAgg(figure)
        anchor_axes, residual_axes = figure.add_subplot(1, 2, 1), figure.add_subplot(1, 2, 2)
        styles = ("-", "--", ":", "-.")
        for index, name in enumerate(rows[0].anchors if rows else []):
            points = np.array([row.anchors[name] for row in rows])
            for axis in range(3):
                if np.ptp(points[:, axis]) > 1e-12:
                    anchor_axes.plot(masses, points[:, axis], color=ANCHOR_COLOR, marker="o", markersize=3,
                                     linestyle=styles[index % len(styles)], label=f"{name} {'xyz'[axis]}")
        anchor_axes.set_xlabel("payload [kg]")
        anchor_axes.set_ylabel("anchor coordinate [m]")
        anchor_axes.grid(True, alpha=0.3)
        if anchor_axes.lines:
            anchor_axes.legend(loc="best", fontsize="small")
        residual_axes.plot(masses, [row.peak for row in rows], color=RESIDUAL_COLOR, marker="o", markersize=3,
                           linewidth=2, label="peak residual")
        residual_axes.axhline(self.max_residual, color="black", linewidth=0.6, linestyle="--", label="limit")
        if np.isfinite(self.max_payload):
            for axes in (anchor_axes, residual_axes):
                axes.axvline(self.max_payload, color="#7f7f7f", linewidth=0.8, linestyle=":")
        residual_axes.set_xlabel("payload [kg]")
        residual_axes.set_ylabel("peak residual torque [N·m]")
        residual_axes.grid(True, alpha=0.3)
        residual_axes.legend(loc="best", fontsize="small")
        figure.suptitle(f"Adjustable anchor against the payload on {self.body!r} "
                        f"(largest balanced: {self.max_payload:.4g} kg)", fontsize="medium")
        if path is not None:
            save_figure(figure, path)
        return figure

    def to_dict(self) -> dict[str, Any]:
        return {"body": self.body, "point": list(self.point), "max_residual": self.max_residual,
                "max_payload": self.max_payload, "rows": [row.to_dict() for row in self.rows]}


@dataclasses.dataclass
class PayloadSweep:
    """Result of :func:`residual_vs_payload`: per payload mass [kg], the peak and RMS residual [N·m]."""

    body: str
    point: tuple[float, ...]
    masses: np.ndarray
    peak: np.ndarray
    rms: np.ndarray

    def table(self) -> str:
        lines = [f"Residual torque against the payload at {list(self.point)} m of {self.body!r} (design fixed)",
                 f"  {'payload [kg]':>12s}{'peak [N·m]':>13s}{'rms [N·m]':>12s}"]
        lines += [f"  {m:12.4g}{p:13.4g}{r:12.4g}" for m, p, r in zip(self.masses, self.peak, self.rms)]
        return "\n".join(lines)

    def plot(self, path: str | Path | None = None, label: str = "fixed design") -> Figure:
        """matplotlib figure: peak and RMS residual against the payload (PNG + SVG at ``path``)."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from springbalance.results.plots import save_figure

        figure = Figure(figsize=(4.6, 3.2), layout="constrained")
        FigureCanvasAgg(figure)
        axes = figure.add_subplot()
        axes.plot(self.masses, self.peak, color=RESIDUAL_COLOR, marker="o", markersize=3, linewidth=2,
                  label=f"{label}: peak")
        axes.plot(self.masses, self.rms, color=RESIDUAL_COLOR, linestyle="--", label=f"{label}: rms")
        axes.set_xlabel("payload [kg]")
        axes.set_ylabel("residual torque [N·m]")
        axes.grid(True, alpha=0.3)
        axes.legend(loc="best", fontsize="small")
        if path is not None:
            save_figure(figure, path)
        return figure

    def to_dict(self) -> dict[str, Any]:
        return {"body": self.body, "point": list(self.point), "masses": self.masses.tolist(),
                "peak": self.peak.tolist(), "rms": self.rms.tolist()}


# ---------------------------------------------------------------------- studies
def payload_range(result: DesignResult, body: str, point: Sequence[float] = (0.0, 0.0, 0.0),
                  max_residual: float | None = None, masses: npt.ArrayLike | None = None,
                  rounds: int = 3, points: int = 9, starts: int = 1) -> PayloadRange:
    """Largest payload an adjustable design can balance, and its anchor against the payload.

    Args:
        result: a :class:`~springbalance.results.result.DesignResult` whose problem has per-scenario
            variables; its shared variables (the spring) are kept, the per-scenario ones
            (within their bounds: the travel of the anchor) are re-fitted per payload by
            minimising that payload's RMS residual.
        body: the body that carries the payload.
        point: where the payload sits on ``body`` (body-frame point [m]).
        max_residual: peak residual torque [N·m] up to which a payload counts as balanced
            (default 1e-6 × the bare mechanism's peak gravity torque: exact balance).
        masses: payloads [kg] for the table (default: 9 from 0 to just past the largest).
        rounds: bracketing of the largest payload: ``rounds`` sweeps of ``points`` masses each.
        points: masses per bracketing sweep (see ``rounds``).
        starts: starts of the multi-start that re-fits the per-scenario variables.
    """
    problem = result.problem
    if not problem.model.per_scenario:
        raise InputError("payload_range needs a design with per-scenario variables (e.g. per_scenario=['s1.b'])")
    point = _checked_point(problem, body, point)
    masses = None if masses is None else _checked_masses(masses)
    springs = _adjustable_springs(problem, result.x)
    if max_residual is None:
        max_residual = 1e-6 * float(np.max(np.abs(problem.base_workspace.kinematics().gravity_torque)))
    elif isinstance(max_residual, bool) or not isinstance(max_residual, (int, float, np.integer, np.floating)) \
            or not (np.isfinite(max_residual) and max_residual > 0):
        raise InputError(f"max residual must be a finite number > 0 [N·m], got {max_residual!r}")
    max_residual = float(max_residual)
    solved: dict[float, PayloadRow] = {}

    def sweep(candidates):
        new = [float(m) for m in candidates if float(m) not in solved]
        if new:
            for row in _solve_payloads(problem, springs, body, point, new, max_residual, starts):
                solved[row.mass] = row

    # bracket [balanced, unbalanced] with one sweep of 0 and geometric masses up to 4^9 × the scale
    scale = max(float(np.max(masses)) if masses is not None and len(masses) else 0.0, 1.0)
    sweep([0.0] + [scale * 4.0**i for i in range(10)])
    low, high = 0.0, None
    for mass in sorted(solved):
        if not solved[mass].balanced:
            high = mass
            break
        low = mass
    if not solved[0.0].balanced:
        max_payload = 0.0
    elif high is None:
        max_payload = float("inf")
    else:
        for _ in range(int(rounds)):
            grid = np.linspace(low, high, int(points) + 2)[1:-1]
            sweep(grid)
            for mass in np.concatenate([[low], grid, [high]]):
                if solved[float(mass)].balanced:
                    low = float(mass)
                else:
                    high = float(mass)
                    break
        # past the end of the travel the residual grows along a straight line: extrapolate it to the limit
        above = sorted(m for m, row in solved.items() if not row.balanced)[:2]
        max_payload = high
        if len(above) == 2 and solved[above[1]].peak > solved[above[0]].peak:
            (m0, m1), (r0, r1) = above, (solved[above[0]].peak, solved[above[1]].peak)
            max_payload = float(np.clip(m0 + (max_residual - r0) * (m1 - m0) / (r1 - r0), low, high))
    if masses is None:
        top = max_payload if np.isfinite(max_payload) else max(solved)
        masses = np.linspace(0.0, 1.25 * top if top > 0 else 1.0, 9)
    sweep(masses)
    rows = [solved[float(m)] for m in masses]
    return PayloadRange(body, point, max_residual, rows, max_payload)


def residual_vs_payload(result: DesignResult, body: str, masses: npt.ArrayLike,
                        point: Sequence[float] = (0.0, 0.0, 0.0), scenario: int = 0) -> PayloadSweep:
    """Peak and RMS residual torque [N·m] of a fixed design (its values in ``scenario``) with each payload."""
    problem = result.problem
    point = _checked_point(problem, body, point)
    masses = _checked_masses(masses)
    springs = problem.scenario_springs(result.x, scenario) if problem.scenarios else result.fixed_springs()
    stacked = DesignProblem(problem.mechanism, problem.base_workspace, springs, objective="rms",
                            weights=problem.weights_by_name(), scenarios=_scenarios(body, point, masses))
    peak, rms = _per_block(stacked, stacked.evaluate(np.zeros(0)).tau, len(masses))
    return PayloadSweep(body, point, masses, peak, rms)


# ---------------------------------------------------------------------- helpers
def _checked_masses(masses) -> np.ndarray:
    """``masses`` [kg] as a 1-D array of finite numbers in [0, MAX_MASS]; InputError naming the first bad one."""
    try:
        values = np.asarray(masses, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"payload masses must be numbers [kg], got {masses!r}") from None
    if values.size == 0:
        raise InputError("give at least one payload mass [kg]")
    for value in values:
        if not (np.isfinite(value) and 0 <= value <= MAX_MASS):
            raise InputError(f"payload mass {value:g} kg: masses must be finite numbers from 0 to {MAX_MASS:g} kg")
    return values


def _checked_point(problem, body: str, point) -> tuple[float, ...]:
    """The payload ``point`` [m] of ``body``: three finite numbers within MAX_DISTANCE of the body's origin."""
    problem.mechanism.frame_id(body)  # an unknown body is named
    try:
        values = np.asarray(point, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"payload point must be three numbers [m], got {point!r}") from None
    if values.shape != (3,) or not np.all(np.isfinite(values)):
        raise InputError(f"payload point must be three finite numbers [m], got {point!r}")
    if float(np.linalg.norm(values)) > MAX_DISTANCE:
        raise InputError(f"payload point {values.tolist()} is {np.linalg.norm(values):.3g} m from the origin of "
                         f"{body!r}; a payload sits within {MAX_DISTANCE:g} m of its body")
    return tuple(values.tolist())


def _scenarios(body, point, masses):
    return [Scenario(f"payload {i}: {m:g} kg", [Payload(body, float(m), point)] if m > 0 else [])
            for i, m in enumerate(masses)]


def _per_block(problem, tau, blocks):
    weighted = np.abs(tau * problem.weights)
    parts = np.split(weighted, blocks, axis=0)
    return (np.array([float(np.max(part)) for part in parts]),
            np.array([float(np.sqrt(np.mean(part**2))) for part in parts]))


def _adjustable_springs(problem, x):
    """The springs with every shared variable fixed at its value in ``x``; per-scenario ones stay free."""
    model = problem.model
    adjustable = {model.base_variables.names[i] for i in model.per_scenario}
    springs = []
    for spring in problem.springs:
        record = spring.to_dict()
        values = model.spring_values(spring, x, 0)
        for key in spring.parameter_units:
            if f"{spring.name}.{key}" not in adjustable:
                record[key] = values[key]
        for end, anchor in spring.anchors.items():
            if not any(name.startswith(f"{spring.name}.{end}.") for name in adjustable):
                record[end] = {"body": anchor.body, "point": model.anchor_point(spring, end, x, 0).tolist()}
        springs.append(spring_from_dict(record))
    return springs


def _solve_payloads(problem, springs, body, point, masses, max_residual, starts):
    stacked = DesignProblem(problem.mechanism, problem.base_workspace, springs, objective="rms",
                            weights=problem.weights_by_name(), scenarios=_scenarios(body, point, masses),
                            per_scenario=problem.per_scenario)
    solution = stacked.solve(starts=starts, progress=False, max_iterations=200, tolerance=1e-12)
    solution = DesignResult(stacked, refine(stacked, solution.x), method=solution.method, status=solution.status)
    peak, rms = _per_block(stacked, solution.evaluation.tau, len(masses))
    model = stacked.model
    names = [model.base_variables.names[i] for i in model.per_scenario]
    ends = [(spring, end) for spring in stacked.springs for end, anchor in spring.anchors.items()
            if any(name.startswith(f"{spring.name}.{end}.") for name in names)]
    rows = []
    for s, mass in enumerate(masses):
        base = model.scenario_vector(solution.x, s)
        variables = {name: float(base[i]) for name, i in zip(names, model.per_scenario)}
        anchors = {f"{spring.name}.{end}": model.anchor_point(spring, end, solution.x, s).tolist()
                   for spring, end in ends}
        rows.append(PayloadRow(float(mass), variables, anchors, float(peak[s]), float(rms[s]),
                               bool(peak[s] <= max_residual)))
    return rows
