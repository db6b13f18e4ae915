r"""Payload studies of a design: how far an adjustable anchor carries, and how a fixed design degrades.

- :func:`springbalance.pipeline.payload.payload_range` (it solves, so it sits in the pipeline): for a design whose problem has per-scenario variables (an
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
from typing import TYPE_CHECKING, Any, Iterable, Sequence

import numpy as np
import numpy.typing as npt

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.problem import DesignProblem
from springbalance.design.scenarios import Payload, Scenario
from springbalance.errors import InputError
from springbalance.results.plots import new_figure, save_figure
from springbalance.springs.laws import Spring

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
        """The row as JSON-friendly data."""
        return {
            "mass": self.mass,
            "variables": self.variables,
            "anchors": {key: list(point) for key, point in self.anchors.items()},
            "peak": self.peak,
            "rms": self.rms,
            "balanced": self.balanced,
        }


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
        """The rows as text: payload [kg], adjustable anchor points [m], peak and RMS residual [N·m]."""
        anchors = list(self.rows[0].anchors) if self.rows else []
        header = (
            f"  {'payload [kg]':>12s}"
            + "".join(f"{name + ' [m]':>28s}" for name in anchors)
            + f"{'peak [N·m]':>13s}{'rms [N·m]':>12s}  balanced"
        )
        lines = [
            f"Payload range: payload at {list(self.point)} m of {self.body!r}, balanced when the peak "
            f"residual ≤ {self.max_residual:.3g} N·m",
            header,
        ]
        for row in self.rows:
            points = "".join(
                f"{'[' + ', '.join(f'{v:+.4f}' for v in row.anchors[name]) + ']':>28s}" for name in anchors
            )
            lines.append(
                f"  {row.mass:12.4g}{points}{row.peak:13.4g}{row.rms:12.4g}  {'yes' if row.balanced else 'no'}"
            )
        lines.append(f"  largest payload balanced: {self.max_payload:.6g} kg")
        return "\n".join(lines)

    def plot(self, path: str | Path | None = None) -> Figure:
        """matplotlib figure: adjustable anchor coordinates and peak residual against the payload
        (also saved as PNG and SVG when ``path`` is given)."""
        rows = sorted(self.rows, key=lambda row: row.mass)
        masses = np.array([row.mass for row in rows])
        figure = new_figure(figsize=(8.4, 3.2), layout="constrained")
        anchor_axes, residual_axes = figure.add_subplot(1, 2, 1), figure.add_subplot(1, 2, 2)
        styles = ("-", "--", ":", "-.")
        for index, name in enumerate(rows[0].anchors if rows else []):
            points = np.array([row.anchors[name] for row in rows])
            for axis in range(3):
                if np.ptp(points[:, axis]) > 1e-12:
                    anchor_axes.plot(
                        masses,
                        points[:, axis],
                        color=ANCHOR_COLOR,
                        marker="o",
                        markersize=3,
                        linestyle=styles[index % len(styles)],
                        label=f"{name} {'xyz'[axis]}",
                    )
        anchor_axes.set_xlabel("payload [kg]")
        anchor_axes.set_ylabel("anchor coordinate [m]")
        anchor_axes.grid(True, alpha=0.3)
        if anchor_axes.lines:
            anchor_axes.legend(loc="best", fontsize="small")
        residual_axes.plot(
            masses,
            [row.peak for row in rows],
            color=RESIDUAL_COLOR,
            marker="o",
            markersize=3,
            linewidth=2,
            label="peak residual",
        )
        residual_axes.axhline(self.max_residual, color="black", linewidth=0.6, linestyle="--", label="limit")
        if np.isfinite(self.max_payload):
            for axes in (anchor_axes, residual_axes):
                axes.axvline(self.max_payload, color="#7f7f7f", linewidth=0.8, linestyle=":")
        residual_axes.set_xlabel("payload [kg]")
        residual_axes.set_ylabel("peak residual torque [N·m]")
        residual_axes.grid(True, alpha=0.3)
        residual_axes.legend(loc="best", fontsize="small")
        figure.suptitle(
            f"Adjustable anchor against the payload on {self.body!r} (largest balanced: {self.max_payload:.4g} kg)",
            fontsize="medium",
        )
        if path is not None:
            save_figure(figure, path)
        return figure

    def to_dict(self) -> dict[str, Any]:
        """The study as JSON-friendly data."""
        return {
            "body": self.body,
            "point": list(self.point),
            "max_residual": self.max_residual,
            "max_payload": self.max_payload,
            "rows": [row.to_dict() for row in self.rows],
        }


@dataclasses.dataclass
class PayloadSweep:
    """Result of :func:`residual_vs_payload`: per payload mass [kg], the peak and RMS residual [N·m]."""

    body: str
    point: tuple[float, ...]
    masses: np.ndarray
    peak: np.ndarray
    rms: np.ndarray

    def table(self) -> str:
        """The sweep as text: payload [kg], peak and RMS residual [N·m]."""
        lines = [
            f"Residual torque against the payload at {list(self.point)} m of {self.body!r} (design fixed)",
            f"  {'payload [kg]':>12s}{'peak [N·m]':>13s}{'rms [N·m]':>12s}",
        ]
        lines += [f"  {m:12.4g}{p:13.4g}{r:12.4g}" for m, p, r in zip(self.masses, self.peak, self.rms)]
        return "\n".join(lines)

    def plot(self, path: str | Path | None = None, label: str = "fixed design") -> Figure:
        """matplotlib figure: peak and RMS residual against the payload (PNG + SVG at ``path``)."""
        figure = new_figure(figsize=(4.6, 3.2), layout="constrained")
        axes = figure.add_subplot()
        axes.plot(
            self.masses, self.peak, color=RESIDUAL_COLOR, marker="o", markersize=3, linewidth=2, label=f"{label}: peak"
        )
        axes.plot(self.masses, self.rms, color=RESIDUAL_COLOR, linestyle="--", label=f"{label}: rms")
        axes.set_xlabel("payload [kg]")
        axes.set_ylabel("residual torque [N·m]")
        axes.grid(True, alpha=0.3)
        axes.legend(loc="best", fontsize="small")
        if path is not None:
            save_figure(figure, path)
        return figure

    def to_dict(self) -> dict[str, Any]:
        """The sweep as JSON-friendly data."""
        return {
            "body": self.body,
            "point": list(self.point),
            "masses": self.masses.tolist(),
            "peak": self.peak.tolist(),
            "rms": self.rms.tolist(),
        }


# ---------------------------------------------------------------------- a fixed design's study
def residual_vs_payload(
    result: EvaluatedDesign,
    body: str,
    masses: npt.ArrayLike,
    point: Sequence[float] = (0.0, 0.0, 0.0),
    scenario: int = 0,
) -> PayloadSweep:
    """Peak and RMS residual torque [N·m] of a fixed design (its values in ``scenario``) with each payload."""
    problem = result.problem
    point = checked_point(problem, body, point)
    masses = checked_masses(masses)
    springs = problem.scenario_springs(result.x, scenario) if problem.scenarios else result.fixed_springs()
    stacked = payload_problem(problem, springs, body, point, masses)
    peak, rms = per_block(stacked, stacked.evaluate(np.zeros(0)).tau, len(masses))
    return PayloadSweep(body, point, masses, peak, rms)


# ---------------------------------------------------------------------- helpers
def payload_problem(
    problem: DesignProblem,
    springs: list[Spring],
    body: str,
    point: tuple[float, ...],
    masses: Iterable[float],
    per_scenario: Sequence[str] = (),
) -> DesignProblem:
    """``problem``'s mechanism, poses and weights with ``springs``, stacked once per payload mass [kg] at ``point``
    [m] of ``body`` (rms objective); ``per_scenario`` names the variables that take one value per payload."""
    return DesignProblem(
        problem.mechanism,
        problem.base_workspace,
        springs,
        objective="rms",
        weights=problem.weights_by_name(),
        scenarios=payload_cases(body, point, masses),
        per_scenario=per_scenario,
    )


def checked_masses(masses: npt.ArrayLike) -> np.ndarray:
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


def checked_point(problem: DesignProblem, body: str, point: Sequence[float]) -> tuple[float, ...]:
    """The payload ``point`` [m] of ``body``: three finite numbers within MAX_DISTANCE of the body's origin."""
    problem.mechanism.frame_id(body)  # an unknown body is named
    try:
        values = np.asarray(point, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"payload point must be three numbers [m], got {point!r}") from None
    if values.shape != (3,) or not np.all(np.isfinite(values)):
        raise InputError(f"payload point must be three finite numbers [m], got {point!r}")
    if float(np.linalg.norm(values)) > MAX_DISTANCE:
        raise InputError(
            f"payload point {values.tolist()} is {np.linalg.norm(values):.3g} m from the origin of "
            f"{body!r}; a payload sits within {MAX_DISTANCE:g} m of its body"
        )
    return tuple(values.tolist())


def payload_cases(body: str, point: tuple[float, ...], masses: Iterable[float]) -> list[Scenario]:
    """One scenario per payload mass [kg] at ``point`` [m] of ``body`` (none for a zero mass)."""
    return [
        Scenario(f"payload {i}: {m:g} kg", [Payload(body, float(m), point)] if m > 0 else [])
        for i, m in enumerate(masses)
    ]


def per_block(problem: DesignProblem, tau: np.ndarray, blocks: int) -> tuple[np.ndarray, np.ndarray]:
    """Peak and RMS of the weighted residual torque [N·m] of each of ``blocks`` equal blocks of samples."""
    weighted = np.abs(tau * problem.weights)
    parts = np.split(weighted, blocks, axis=0)
    return (
        np.array([float(np.max(part)) for part in parts]),
        np.array([float(np.sqrt(np.mean(part**2))) for part in parts]),
    )
