r"""How far an adjustable anchor carries: the largest payload a design balances, and its anchor against the payload.

:func:`payload_range`: for a design whose problem has per-scenario variables (an adjustable anchor such as
a slider on a link, a preload), keep the shared variables (the spring) at the design's values and re-fit
only the per-scenario ones for each payload ``m`` [kg] at a point of a body. Returns the anchor position
against the payload (a table and a plot) and the largest payload still balanced to a given peak residual
torque, found by bracketing and, past the end of the travel, by the straight line that the residual follows
there. For a single link with a zero-free-length spring (docs/model.md §9) the anchor moves by
:math:`\Delta b = \Delta m\,w\,g/(k a)` and the largest payload for travel up to ``b_max`` is
:math:`k a (b_{max} - b)/(w g)` (R4).

All payloads of one sweep are solved at once as one stacked problem (one scenario per payload,
:mod:`springbalance.design.scenarios`), whose per-scenario variables are independent once the shared ones
are fixed. The fixed design's counterpart, :func:`springbalance.results.payload.residual_vs_payload`, only
evaluates. Units: kg, m, N·m.
"""

from __future__ import annotations

from typing import Iterable, Sequence

import numpy as np
import numpy.typing as npt

from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import refine
from springbalance.errors import InputError
from springbalance.pipeline.sequence import run_steps
from springbalance.pipeline.state import SolveOptions
from springbalance.results.payload import (
    PayloadRange,
    PayloadRow,
    checked_masses,
    checked_point,
    payload_problem,
    per_block,
)
from springbalance.springs.laws import Spring
from springbalance.springs.records import spring_from_dict


def payload_range(
    result: EvaluatedDesign,
    body: str,
    point: Sequence[float] = (0.0, 0.0, 0.0),
    max_residual: float | None = None,
    masses: npt.ArrayLike | None = None,
    rounds: int = 3,
    points: int = 9,
    starts: int = 1,
) -> PayloadRange:
    """Largest payload an adjustable design can balance, and its anchor against the payload.

    Args:
        result: a design (:class:`~springbalance.design.evaluated.EvaluatedDesign`) whose problem has per-scenario
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
    point = checked_point(problem, body, point)
    masses = None if masses is None else checked_masses(masses)
    springs = _adjustable_springs(problem, result.x)
    max_residual = _checked_max_residual(problem, max_residual)
    solves = _PayloadSolves(problem, springs, body, point, max_residual, starts)
    max_payload = _largest_payload(solves, masses, rounds, points)
    if masses is None:
        top = max_payload if np.isfinite(max_payload) else max(solves.solved)
        masses = np.linspace(0.0, 1.25 * top if top > 0 else 1.0, 9)
    solves.sweep(masses)
    rows = [solves.solved[float(m)] for m in masses]
    return PayloadRange(body, point, max_residual, rows, max_payload)


def _checked_max_residual(problem: DesignProblem, max_residual: float | None) -> float:
    """The peak residual [N·m] up to which a payload counts as balanced; default 1e-6 × the bare
    mechanism's peak gravity torque (exact balance)."""
    if max_residual is None:
        max_residual = 1e-6 * float(np.max(np.abs(problem.base_workspace.kinematics().gravity_torque)))
    elif (
        isinstance(max_residual, bool)
        or not isinstance(max_residual, (int, float, np.integer, np.floating))
        or not (np.isfinite(max_residual) and max_residual > 0)
    ):
        raise InputError(f"max residual must be a finite number > 0 [N·m], got {max_residual!r}")
    return float(max_residual)


class _PayloadSolves:
    """The payloads solved so far (mass [kg] → :class:`PayloadRow`); :meth:`sweep` solves the new ones at once."""

    def __init__(
        self,
        problem: DesignProblem,
        springs: list[Spring],
        body: str,
        point: tuple[float, ...],
        max_residual: float,
        starts: int,
    ) -> None:
        self.problem, self.springs, self.body, self.point = problem, springs, body, point
        self.max_residual, self.starts = max_residual, starts
        self.solved: dict[float, PayloadRow] = {}

    def sweep(self, candidates: Iterable[float]) -> None:
        """Solve the masses [kg] of ``candidates`` not solved yet (one stacked problem)."""
        new = [float(m) for m in candidates if float(m) not in self.solved]
        if new:
            for row in _solve_payloads(
                self.problem, self.springs, self.body, self.point, new, self.max_residual, self.starts
            ):
                self.solved[row.mass] = row


def _largest_payload(solves: _PayloadSolves, masses: np.ndarray | None, rounds: int, points: int) -> float:
    """The largest balanced payload [kg]: bracketed by a geometric sweep, narrowed by ``rounds`` sweeps of
    ``points`` masses, and past the end of the travel extrapolated along the residual's straight line."""
    solved = solves.solved
    # bracket [balanced, unbalanced] with one sweep of 0 and geometric masses up to 4^9 × the scale
    scale = max(float(np.max(masses)) if masses is not None and len(masses) else 0.0, 1.0)
    solves.sweep([0.0] + [scale * 4.0**i for i in range(10)])
    low, high = 0.0, None
    for mass in sorted(solved):
        if not solved[mass].balanced:
            high = mass
            break
        low = mass
    if not solved[0.0].balanced:
        return 0.0
    if high is None:
        return float("inf")
    for _ in range(int(rounds)):
        grid = np.linspace(low, high, int(points) + 2)[1:-1]
        solves.sweep(grid)
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
        max_payload = float(np.clip(m0 + (solves.max_residual - r0) * (m1 - m0) / (r1 - r0), low, high))
    return max_payload


def _adjustable_springs(problem: DesignProblem, x: np.ndarray) -> list[Spring]:
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


def _solve_payloads(
    problem: DesignProblem,
    springs: list[Spring],
    body: str,
    point: tuple[float, ...],
    masses: list[float],
    max_residual: float,
    starts: int,
) -> list[PayloadRow]:
    """Every payload of ``masses`` [kg] as one scenario of a stacked problem, solved at once, then refined."""
    stacked = payload_problem(problem, springs, body, point, masses, problem.per_scenario)
    solution = run_steps(stacked, SolveOptions(starts=starts, progress=False, max_iterations=200, tolerance=1e-12))
    design = EvaluatedDesign(stacked, refine(stacked, solution.x), method=solution.method, status=solution.status)
    peak, rms = per_block(stacked, design.evaluation.tau, len(masses))
    model = stacked.model
    names = [model.base_variables.names[i] for i in model.per_scenario]
    ends = [
        (spring, end)
        for spring in stacked.springs
        for end, anchor in spring.anchors.items()
        if any(name.startswith(f"{spring.name}.{end}.") for name in names)
    ]
    rows = []
    for s, mass in enumerate(masses):
        base = model.scenario_vector(design.x, s)
        variables = {name: float(base[i]) for name, i in zip(names, model.per_scenario)}
        anchors = {
            f"{spring.name}.{end}": model.anchor_point(spring, end, design.x, s).tolist() for spring, end in ends
        }
        rows.append(
            PayloadRow(float(mass), variables, anchors, float(peak[s]), float(rms[s]), bool(peak[s] <= max_residual))
        )
    return rows
