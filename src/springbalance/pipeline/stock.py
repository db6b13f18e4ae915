"""Stock springs chosen for a continuous design: each coil spring replaced by its nearest catalogue part,
the anchors re-optimised (the records and the part model are :mod:`springbalance.design.stock`, whose
documentation gives the method)."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from springbalance.design.objectives import Objective, ScenarioAggregate
from springbalance.design.problem import DesignProblem
from springbalance.design.stock import (
    CANDIDATES,
    StockChoice,
    StockPart,
    StockSelection,
    StockTrial,
    part_distance,
    part_spring,
    stock_kind,
    warm_started,
)
from springbalance.design.stock_checks import fatigue_of, spring_duty, tolerance_of
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.errors import InputError, SolverError
from springbalance.pipeline.sequence import run_steps
from springbalance.pipeline.state import SolveOptions
from springbalance.springs.fatigue import Duty
from springbalance.springs.laws import Spring
from springbalance.springs.params import Free


def select_stock(
    problem: DesignProblem,
    continuous: np.ndarray | object,
    parts: Sequence[StockPart],
    *,
    candidates: int = CANDIDATES,
    starts: int = 2,
    seed: int = 0,
    method: str = "auto",
    max_iterations: int = 100,
    tolerance: float = 1e-8,
    workers: int | None = None,
    tolerances: ToleranceSpec | None = None,
) -> StockSelection:
    """Replace each extension and compression spring of a continuous design by a catalogue part.

    Args:
        problem: the continuous design problem.
        continuous: its optimum: a design vector or a result with an ``x`` (a ``DesignResult``).
        parts: the catalogue (:class:`StockPart`, e.g. from :func:`springbalance.io.catalogue.read_catalogue`).
        candidates: parts tried per spring (the nearest by :func:`part_distance`).
        starts: starts of the solve of each candidate (:meth:`DesignProblem.solve`); its first
            start is the warm start at the current optimum.
        seed: seed of those starts.
        method: solver method of those solves.
        max_iterations: iteration budget of each start.
        tolerance: stopping tolerance of the least squares.
        workers: processes that run the starts of each solve at once (:meth:`DesignProblem.solve`).
        tolerances: the spring tolerances the chosen parts are checked with (None: grade 2 for every coil).

    Returns a :class:`StockSelection`. Raises :class:`SolverError` naming the spring when none of
    its candidates (or no part of its type) gives a feasible design, :class:`InputError` when the
    problem has no spring a part can replace or the catalogue is empty.
    """
    x = np.asarray(getattr(continuous, "x", continuous), dtype=float)
    parts = list(parts)
    names = _stock_springs(problem, x, parts, candidates)
    objective = _inner_objective(problem)
    continuous_value = problem.objective_at(x)
    options = SolveOptions(
        starts=int(starts),
        seed=int(seed),
        method=method,
        progress=False,
        max_iterations=int(max_iterations),
        tolerance=float(tolerance),
        workers=workers,
    )
    current, current_x = problem, x
    choices, notes = [], []
    for name in names:
        column = [spring.name for spring in current.springs].index(name)
        spring = current.springs[column]
        kind = stock_kind(spring)
        assert kind is not None  # only springs of a stock kind are named above
        evaluation = current.evaluate(current_x)
        values = current.model.spring_values(spring, current_x)
        lengths, forces = evaluation.lengths[:, column], evaluation.tensions[:, column]
        same_kind = [part for part in parts if part.kind == kind]
        if not same_kind:
            raise SolverError(f"no stock part fits spring {name!r}: the catalogue holds no {kind} springs")
        ranked = sorted(((part_distance(part, lengths, forces), part) for part in same_kind), key=lambda pair: pair[0])[
            : int(candidates)
        ]
        trials, best = _try_parts(current, current_x, name, ranked, objective, options, spring_duty(spring))
        if best is None:
            tried = "; ".join(f"{trial.part.part_number}: {trial.status}" for trial in trials)
            raise SolverError(
                f"no stock part fits spring {name!r}: none of the {len(trials)} {kind} parts nearest its "
                f"design (tension {np.min(forces):.4g} … {np.max(forces):.4g} N over "
                f"{np.min(lengths):.4g} … {np.max(lengths):.4g} m) gives a feasible design ({tried})"
            )
        value, part, current, current_result, dropped = best
        current_x = current_result.x
        notes += [f"per-scenario variable {entry!r} is fixed by the stock part of {name!r}" for entry in dropped]
        designed = {
            **values,
            "min_length": float(np.min(lengths)),
            "max_length": float(np.max(lengths)),
            "min_force": float(np.min(forces)),
            "max_force": float(np.max(forces)),
        }
        choices.append(StockChoice(name, kind, designed, part, value, trials))
    selection = StockSelection(
        current_result,
        problem.objective.name,
        problem.objective.unit,
        continuous_value,
        choices[-1].objective,
        choices,
        notes,
    )
    return _checked(selection, problem, tolerances)


def _checked(selection: StockSelection, problem: DesignProblem, spec: ToleranceSpec | None) -> StockSelection:
    """``selection`` with the fatigue of each chosen part (under the duty of the spring it replaced) and the
    tolerance analysis of the stock design (:mod:`springbalance.design.stock_checks`)."""
    result = selection.result
    evaluation = result.evaluation
    duties = {spring.name: spring_duty(spring) for spring in problem.springs}
    analysis = tolerance_of(result.problem, result.x, evaluation.tau, evaluation.lengths, spec)
    boxes = {box.name: box.to_dict() for box in analysis.boxes}
    travel = {row["name"]: row["travel"] for row in analysis.travel}
    for choice in selection.choices:
        choice.fatigue = fatigue_of(result.problem, result.x, evaluation.tensions, choice.spring, duties[choice.spring])
        if choice.spring in boxes:
            choice.tolerance = {"box": boxes[choice.spring], "travel": travel[choice.spring]}
    selection.tolerance = analysis
    return selection


def _stock_springs(problem: DesignProblem, x: np.ndarray, parts: list[StockPart], candidates: int) -> list[str]:
    """The names of the springs a part can replace (extension and compression springs without a part number),
    after checking the design vector, the catalogue and the candidate count."""
    if x.shape != (problem.variables.size,):
        raise InputError(f"the continuous design has {x.size} values, the problem {problem.variables.size}")
    if not parts:
        raise InputError("the stock catalogue holds no parts")
    if int(candidates) < 1:
        raise InputError(f"candidates must be ≥ 1, got {candidates}")
    names = [
        spring.name
        for spring in problem.springs  # (a problem names every spring)
        if spring.name is not None and stock_kind(spring) is not None and getattr(spring, "part_number", None) is None
    ]
    if not names:
        raise InputError(
            "no spring to take from the catalogue: stock parts replace extension and compression "
            "springs without a part_number; this design has "
            + ", ".join(f"{spring.name} ({spring.kind})" for spring in problem.springs)
        )
    return names


def _try_parts(
    current: DesignProblem,
    current_x: np.ndarray,
    name: str,
    ranked: list[tuple[float, StockPart]],
    objective: Objective,
    options: SolveOptions,
    duty: Duty,
) -> tuple[list[StockTrial], tuple | None]:
    """Each ranked part in place of spring ``name``, solved warm from ``current_x``: the trials, and the best
    feasible one as ``(objective value, part, problem, result, dropped per-scenario variables)`` (None if none).
    A part that does not survive ``duty`` at its optimum (:func:`~springbalance.design.stock_checks.fatigue_of`)
    is not feasible."""
    warm = warm_started(current, current_x)
    trials: list[StockTrial] = []
    best = None
    for distance, part in ranked:
        springs = [part_spring(part, s) if s.name == name else s for s in warm]
        trial_problem, dropped = _like(current, springs, objective)
        try:
            result = run_steps(trial_problem, options)
        except SolverError as error:
            trials.append(StockTrial(part, distance, None, " ".join(str(error).split())))
            continue
        value = trial_problem.objective_value(result.evaluation)
        fatigue = fatigue_of(trial_problem, result.x, result.evaluation.tensions, name, duty)
        if not fatigue.holds:
            trials.append(
                StockTrial(part, distance, None, f"fails fatigue ({fatigue.failing()}) at objective {value:.6g}")
            )
            continue
        trials.append(StockTrial(part, distance, value, result.status))
        if best is None or value < best[0]:
            best = (value, part, trial_problem, result, dropped)
    return trials, best


def _inner_objective(problem: DesignProblem) -> Objective:
    """The objective to hand a new problem (a scenario aggregate is rebuilt from its inner objective)."""
    return problem.objective.inner if isinstance(problem.objective, ScenarioAggregate) else problem.objective


def _like(problem: DesignProblem, springs: list[Spring], objective: Objective) -> tuple[DesignProblem, list[str]]:
    """A problem like ``problem`` with other springs (its options kept: ``no_joint_worse`` too, so that a part's
    re-solve keeps each weighted joint within the bare arm's peak when the user asked for it); per-scenario entries
    that no longer name a variable (a parameter the stock part fixed) are dropped and returned."""
    keep: list[str] = []
    dropped: list[str] = []
    variables = _variable_names(springs)
    for entry in problem.per_scenario:
        matches = any(name == entry or name.startswith(entry + ".") for name in variables)
        (keep if matches else dropped).append(entry)
    return problem.with_springs(springs, objective=objective, per_scenario=keep), dropped


def _variable_names(springs: list[Spring]) -> list[str]:
    """The design variable names of ``springs`` (as :class:`TorqueModel` names them)."""
    names = []
    for spring in springs:
        for end, anchor in spring.anchors.items():
            names += [f"{spring.name}.{end}.{label}" for label in anchor.region().labels]
        names += [
            f"{spring.name}.{key}"
            for key, value in spring.parameters.items()
            if isinstance(value, Free) and value.upper > value.lower
        ]
    return names
