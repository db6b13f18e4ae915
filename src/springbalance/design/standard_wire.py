"""Standard wire: a helical spring's wire diameter rounded to the preferred series, the rest re-optimised.

The solver treats the wire diameter ``d`` [m] of a coil as continuous. A spring maker draws wire
in preferred sizes (:data:`~springbalance.springs.sizing.PREFERRED_WIRE_DIAMETERS`, within the
material's range, or the sizes a user's spring maker stocks: ``solve.wire_sizes``, :func:`checked_wire_sizes`). :func:`round_wires` takes the continuous optimum and, one coil after the other,
fixes its ``d`` to the preferred size just below and just above, re-optimises every other
variable from the current design, and keeps the better feasible one. The two candidates are two
starts of one solve of the same problem with the rounded wires held, each warm from the current
design's multipliers when IPOPT found it, so that they run at once on the pool's workers. It
reports what the rounding cost: the objective before and after, and each spring's ``d``.

With several coils, one coil after the other costs one solve per coil. A coil's rate
``k = G d⁴/(8 D³ n)`` and its stress ``8 K F D/(π d³)`` keep their values when ``d`` moves to a
nearby size and ``D`` and ``n`` follow it, so the wires rarely interact: :func:`round_wires` first
solves once with *every* wire held, from several starts at once (every wire at its nearest preferred size;
every wire at its other neighbour; every wire at its nearest but one at its other: :func:`_combinations`), and
keeps the best feasible one when it costs at most :data:`JOINT_ACCEPT` of the continuous objective's distance
to the unbalanced one. Only when no start is feasible, or the joint rounding costs more, does it go coil by
coil as above.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from springbalance.design.objectives import percent_change
from springbalance.design.solvers import Solution, StartRecord, solve_problem
from springbalance.design.worse_joints import weighted_joints_made_worse
from springbalance.errors import InputError, SolverError
from springbalance.springs.params import Free
from springbalance.springs.sizing import PREFERRED_WIRE_DIAMETERS

if TYPE_CHECKING:
    from springbalance.design.problem import DesignProblem

WIRE = "wire_diameter"
#: the joint rounding (every wire at once) is kept when it raises the objective by at most this fraction of
#: the gap between the continuous optimum and the unbalanced arm's objective
JOINT_ACCEPT = 0.05
#: a continuous wire within this fraction of its nearest standard size is that size: the joint rounding does not
#: also start from it at its other neighbour (:func:`_combinations`)
AT_SIZE = 0.01
#: the largest wire size [m] a list of sizes may hold: a larger one is a size in millimetres given as metres
LARGEST_WIRE = 0.05


@dataclasses.dataclass
class WireRounding:
    """What rounding the wires to standard sizes cost.

    Attributes:
        continuous_objective: the objective of the continuous optimum (in the objective's unit).
        objective: the objective after rounding.
        wires: spring name → ``(continuous d, standard d)`` [m].
        unrounded: springs left with a continuous wire, with the reason.
    """

    continuous_objective: float
    objective: float
    wires: dict[str, tuple[float, float]]
    unrounded: dict[str, str] = dataclasses.field(default_factory=dict)

    @property
    def cost_percent(self) -> float:
        """How much worse the objective got [%] (negative: better)."""
        return percent_change(self.continuous_objective, self.objective)

    def to_dict(self) -> dict:
        return {
            "continuous_objective": self.continuous_objective,
            "objective": self.objective,
            "cost_percent": self.cost_percent,
            "wires": {name: {"continuous": pair[0], "standard": pair[1]} for name, pair in self.wires.items()},
            "unrounded": dict(self.unrounded),
        }


def coils_with_free_wire(problem: DesignProblem) -> list:
    """The coil springs whose wire diameter is a design variable."""
    return [
        spring
        for spring in problem.springs
        if hasattr(spring, "spec_sheet") and isinstance(spring.parameters.get(WIRE), Free)
    ]


def checked_wire_sizes(sizes: Any, label: str = "wire_sizes") -> tuple[float, ...]:
    """``sizes``, the wire diameters [m] a spring maker draws, as a sorted tuple; InputError ``"<label>: ..."`` naming
    the value when it is not a non-empty list of distinct numbers in ``(0, LARGEST_WIRE)``."""
    if isinstance(sizes, (str, bytes)) or not hasattr(sizes, "__iter__"):
        raise InputError(f"{label}: expected a list of wire diameters [m], got {sizes!r}")
    values = list(sizes)
    if not values or any(
        isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) for v in values
    ):
        raise InputError(f"{label}: expected a non-empty list of wire diameters [m], got {values!r}")
    for value in values:
        if not 0 < value < LARGEST_WIRE:
            hint = f" (diameters are in metres ({value:g} mm is {value * 1e-3:g}))" if value >= LARGEST_WIRE else ""
            raise InputError(f"{label}: each wire diameter must lie in (0, {LARGEST_WIRE:g}) m, got {value!r}{hint}")
    if len(set(values)) != len(values):
        raise InputError(f"{label}: the sizes must be distinct, got {values!r}")
    return tuple(sorted(float(v) for v in values))


def standard_neighbours(
    diameter: float, lower: float, upper: float, sizes: Sequence[float] | None = None
) -> list[float]:
    """The standard wire sizes just below and just above ``diameter`` [m], within ``[lower, upper]``: of ``sizes``
    [m], default the preferred series."""
    series = PREFERRED_WIRE_DIAMETERS if sizes is None else sizes
    within = np.array([d for d in series if lower * (1 - 1e-9) <= d <= upper * (1 + 1e-9)])
    if within.size == 0:
        return []
    below, above = within[within <= diameter], within[within >= diameter]
    return sorted(
        {float(value) for value in ([below.max()] if below.size else []) + ([above.min()] if above.size else [])}
    )


def round_wires(
    problem: DesignProblem, solution: Solution, sizes: Sequence[float] | None = None, **solve_options: Any
) -> tuple[Solution, WireRounding]:
    """Fix every coil's wire to a standard size and re-optimise the rest (see the module docstring).

    Returns the solution of ``problem`` with the standard wires (the wire variables at their
    standard values) and the :class:`WireRounding`. ``sizes``: the standard sizes [m] (default the preferred
    series). ``solve_options`` go to :func:`~springbalance.design.solvers.solve_problem` (``method``,
    ``max_iterations``, ...).
    """
    names = problem.variables.names
    x = np.array(solution.x, dtype=float)
    continuous = problem.objective_at(x)
    joint = _joint_rounding(problem, solution, continuous, sizes, solve_options)
    if joint is not None:
        return joint
    fixed: dict[str, float] = {}  # variable name → standard wire [m]
    rounding = WireRounding(continuous, continuous, {})
    best_solution, multipliers = solution, solution.multipliers
    for spring in coils_with_free_wire(problem):
        name = f"{spring.name}.{WIRE}"
        if name not in names:  # a per-scenario wire: one value per scenario, left continuous
            rounding.unrounded[spring.name] = "its wire diameter is a per-scenario variable"
            continue
        free = spring.parameters[WIRE]
        value = x[names.index(name)]
        candidates = standard_neighbours(value, float(free.lower), float(free.upper), sizes)
        best = _best_candidate(problem, x, multipliers, fixed, name, candidates, solve_options)
        if best is None:
            rounding.unrounded[spring.name] = (
                "no standard wire within its bounds gives a feasible design"
                if candidates
                else "no standard wire size lies within its bounds"
            )
            continue
        objective, candidate, x, found = best
        multipliers = found.multipliers
        fixed[name] = candidate
        rounding.wires[spring.name] = (float(value), candidate)
        rounding.objective = objective
        best_solution = Solution(
            x,
            solution.starts,
            solution.method,
            solution.seed,
            f"{solution.status}; wire of {', '.join(key.removesuffix('.' + WIRE) for key in fixed)} "
            f"at standard sizes ({found.status})",
            multipliers,
        )
    return best_solution, rounding


def _best_candidate(
    problem: DesignProblem,
    x: np.ndarray,
    multipliers: np.ndarray | None,
    fixed: dict[str, float],
    name: str,
    candidates: list[float],
    solve_options: dict[str, Any],
) -> tuple[float, float, np.ndarray, StartRecord] | None:
    """``(objective, candidate, design, record)`` of the best feasible re-solve with wire ``name`` at one
    of ``candidates`` (and the wires of ``fixed`` held), or None. The candidates are starts of one solve
    of the same problem (at once on the pool's workers), each warm from ``x`` and ``multipliers``."""
    if not candidates:
        return None
    names = problem.variables.names
    held = [names.index(key) for key in fixed] + [names.index(name)]
    starts = np.repeat(x[None, :], len(candidates), axis=0)
    starts[:, held[:-1]] = list(fixed.values())
    starts[:, held[-1]] = candidates
    try:  # the same problem with these wires held, warm from the current design and its multipliers
        found = solve_problem(
            problem,
            starts=len(candidates),
            initial=starts,
            multipliers=multipliers,
            fixed=[*fixed, name],
            **solve_options,
        )
    except SolverError:
        return None
    ranked = []
    for record in found.starts:
        if not record.feasible:
            continue
        design = np.array(record.x, dtype=float)
        design[held] = starts[record.index, held]  # exactly the standard sizes
        objective = problem.objective_at(design)
        ranked.append((_refused(problem, design), objective, record.index, design, record))
    if not ranked:
        return None
    _, objective, index, design, record = min(ranked, key=lambda item: item[:3])
    return objective, candidates[index], design, record


def _refused(problem: DesignProblem, design: np.ndarray) -> bool:
    """Whether ``design`` carries a weighted joint worse than the bare arm (:mod:`springbalance.design.worse_joints`):
    a rounding that does is kept only when none of the others avoids it. ur5-mounted-coils-clear at seed 1: the
    lowest objective of the joint rounding (3.7691 N·m) raised the elbow's peak above the bare arm's (exit 3)."""
    return bool(weighted_joints_made_worse(problem, design))


def _combinations(choices: list[list[float]], values: list[float]) -> list[list[float]]:
    """The sets of standard wires the joint rounding starts from, one per coil in each, from each coil's
    ``[nearest, other]`` neighbour (the same size twice when it has one) of its continuous wire ``values`` [m]:
    every coil at its nearest size, every coil at its other one, and every coil at its nearest but one at its other,
    for each coil whose continuous wire lies more than :data:`AT_SIZE` from its nearest size (a wire that is a
    standard size already moves a whole step away from its optimum); sets that repeat one before are left out.
    One coil's wire moved to its other neighbour can cost much less than the nearest sizes together: the UR5
    example at seed 0 rounded its four wires at 4.2860 N·m RMS (its elbow cut 43.08 → 41.69 %), and with the elbow
    coil's wire at 2.5 mm instead of 2.2 at 4.2594."""
    nearest = [pair[0] for pair in choices]
    found = [nearest, [pair[1] for pair in choices]]
    for index, (pair, value) in enumerate(zip(choices, values)):
        if abs(value - pair[0]) > AT_SIZE * pair[0]:
            found.append(nearest[:index] + [pair[1]] + nearest[index + 1 :])
    distinct: list[list[float]] = []
    for combination in found:
        if combination not in distinct:
            distinct.append(combination)
    return distinct


def _joint_rounding(
    problem: DesignProblem,
    solution: Solution,
    continuous: float,
    sizes: Sequence[float] | None,
    solve_options: dict[str, Any],
) -> tuple[Solution, WireRounding] | None:
    """Every coil's wire rounded at once (see the module docstring), or None to go coil by coil: fewer than two
    coils to round, a per-scenario wire, neither start feasible, or a cost above :data:`JOINT_ACCEPT`."""
    names = problem.variables.names
    x = np.array(solution.x, dtype=float)
    wires: list[tuple[str, str, float, list[float]]] = []  # (spring, variable, continuous d, [nearest, other])
    for spring in coils_with_free_wire(problem):
        name = f"{spring.name}.{WIRE}"
        if name not in names:
            return None
        free = spring.parameters[WIRE]
        value = float(x[names.index(name)])
        candidates = sorted(
            standard_neighbours(value, float(free.lower), float(free.upper), sizes), key=lambda d: abs(d - value)
        )
        if not candidates:
            return None
        wires.append((spring.name, name, value, candidates + candidates[:1]))
    if len(wires) < 2:
        return None
    held = [names.index(name) for _, name, _, _ in wires]
    combinations = _combinations([choices for _, _, _, choices in wires], [value for _, _, value, _ in wires])
    starts = np.repeat(x[None, :], len(combinations), axis=0)
    starts[:, held] = combinations
    try:
        found = solve_problem(
            problem,
            starts=len(combinations),
            initial=starts,
            multipliers=solution.multipliers,
            fixed=[name for _, name, _, _ in wires],
            **solve_options,
        )
    except SolverError:
        return None
    feasible = [record for record in found.starts if record.feasible]
    if not feasible:
        return None
    results = []
    for record in feasible:
        design = np.array(record.x, dtype=float)
        design[held] = starts[record.index, held]  # exactly the standard sizes
        objective = problem.objective_at(design)
        results.append((_refused(problem, design), objective, record.index, design, record))
    _, objective, index, design, record = min(results, key=lambda item: item[:3])
    kinematics = problem.workspace.kinematics()  # the arm without springs: gravity alone
    unbalanced = problem.objective.value(
        kinematics.gravity_torque * problem.weights, kinematics.potential, problem.path_steps
    )
    if objective - continuous > JOINT_ACCEPT * max(unbalanced - continuous, 0.0):
        return None
    rounding = WireRounding(
        continuous,
        objective,
        {spring: (value, float(starts[index, column])) for (spring, _, value, _), column in zip(wires, held)},
    )
    status = (
        f"{solution.status}; wire of {', '.join(spring for spring, _, _, _ in wires)} at standard sizes, "
        f"rounded together ({record.status})"
    )
    return Solution(design, solution.starts, solution.method, solution.seed, status, record.multipliers), rounding
