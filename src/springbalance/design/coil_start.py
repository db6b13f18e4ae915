"""A first guess for helical coil springs: solve the ideal twin, then wind a coil for its law.

A coil's rate ``k = G d⁴/(8 D³ n)`` is nonlinear in its variables, and most points of the bounds
of ``(d, D, n)`` are far from useful; the ideal law's ``(k, l0, F0)`` is linear where a coil is
not, and its least-squares solve is quick. So :func:`coil_start` first solves the *twin*
problem, where every coil is the ideal law of its kind with the same anchors, then, per coil,
picks the wire ``d`` (preferred sizes within its bounds) and index ``C`` whose coil has the
twin's rate and comes closest to its free length (extension: ``d (n + 1) + 2 (D − d)``),
within the index range and the envelope, with the initial tension clipped into the band that
can be wound at that index. The twin is solved to a relative cost change of
:data:`TWIN_TOLERANCE` only. The result is a design vector of the real problem (anchors from
the twin) for the solver's first start; the rules themselves are the solver's job. :func:`ideal_twin_start` also
returns what the twin achieved (:class:`~springbalance.design.twin.TwinRecord`), the reference a report
compares the finished coils with.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from springbalance.design import clearance_rows, clearance_starts
from springbalance.design.clearance import LinearRows, stacked_rows
from springbalance.design.clearance_sides import side_rows
from springbalance.design.solvers import Solution, solve_problem
from springbalance.design.twin import TwinRecord, twin_record
from springbalance.errors import SolverError
from springbalance.model.collision import DEFAULT_RADIUS
from springbalance.springs.fatigue import CEILING, FLOOR, force_range
from springbalance.springs.laws import Spring
from springbalance.springs.laws.coil import HelicalCoilSpring
from springbalance.springs.laws.compression import CompressionSpring
from springbalance.springs.laws.extension import ExtensionSpring
from springbalance.springs.laws.helical_compression import HelicalCompressionSpring
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
from springbalance.springs.params import Free
from springbalance.springs.sizing import PREFERRED_WIRE_DIAMETERS, initial_stress_band

if TYPE_CHECKING:
    from springbalance.design.problem import DesignProblem


#: the twin's least squares stop when a step lowers its cost by less than this fraction (a first guess
#: need not be converged further: winding each coil for its law changes the cost far more)
TWIN_TOLERANCE = 1e-4

#: a twin's force cap binds when its largest force comes within this fraction of it
CAP_SLACK = 1e-3


def coil_springs(problem: DesignProblem) -> list[HelicalCoilSpring]:
    """The helical coil springs of ``problem`` that have free variables."""
    return [
        spring
        for spring in problem.springs
        if isinstance(spring, HelicalCoilSpring)
        and hasattr(spring, "spec_sheet")
        and any(isinstance(value, Free) for value in spring.parameters.values())
    ]


def coil_start(problem: DesignProblem, **solve_options: Any) -> np.ndarray | None:
    """A design vector of ``problem`` to start from (see the module docstring); None when the twin fails."""
    start = coil_starts(problem, 1, **solve_options)
    return None if start is None else start.starts[0]


#: what a coil problem's twin is, in the words of its :class:`~springbalance.design.twin.TwinRecord`
TWIN_SOURCE = "the same anchors with ideal springs in place of the coils"
#: the same for a problem with a routed coil (whose twin keeps the coil's path and cable)
ROUTED_TWIN_SOURCE = "the same paths and cables with ideal springs in place of the coils"


@dataclasses.dataclass(frozen=True)
class TwinStart:
    """Where the coils start: the ideal twin's designs wound into coils.

    Attributes:
        starts: design vectors of the problem (rows, best first): with :attr:`rows`, the twin's fitted design
            first, then its distinct optima before the fit.
        twin: the twin problem (every free coil replaced by the ideal law of its kind, a routed coil with its
            path and cable).
        twin_x: the twin's optimum [physical units of ``twin``].
        record: the :class:`~springbalance.design.twin.TwinRecord` of that optimum.
        rows: the linear rows of the twin's fit to the arm (clearance, mounting), over the anchors the coils share
            with it, or None when the problem asks for no fit (or the fit did not converge).
    """

    starts: np.ndarray
    twin: DesignProblem
    twin_x: np.ndarray
    record: TwinRecord
    rows: LinearRows | None = None


def coil_starts(problem: DesignProblem, count: int, **solve_options: Any) -> TwinStart | None:
    """Up to ``count`` design vectors of ``problem`` to start from (rows, best first): the twin's distinct
    feasible starts, best first, each with its coils wound for its laws (see the module docstring). None when
    the problem has no free coil or the twin fails. The twin's multi-start finds several basins (anchor
    layouts); the coil solve starts in each of them rather than at Sobol points of the coils' variables, most
    of which are far from any useful coil."""
    coils = coil_springs(problem)
    if not coils:
        return None
    twin = _twin_problem(problem, coils)
    # only a first guess: winding the coils moves the design far more than this fraction of its cost
    options = {**solve_options, "tolerance": max(solve_options.get("tolerance", 0.0), TWIN_TOLERANCE)}
    try:
        found = solve_problem(twin, **options)
    except SolverError:
        return None
    record = _ideal_record(problem, coils, twin, found, options)
    if clearance_starts.fitted_to_arm(problem):
        fitted = _fitted_twin(problem, coils, twin, found, options)
        if fitted is not None:  # the coils start from the twin's fitted design, inside its rows
            solution, rows = fitted
            start = _wound(problem, twin, coils, np.asarray(solution.x, dtype=float))
            others = _distinct_starts(problem, twin, coils, found, count - 1, np.asarray(solution.x, dtype=float))
            return TwinStart(np.vstack([start[None, :], others]), twin, np.asarray(found.x, dtype=float), record, rows)
    return TwinStart(
        _distinct_starts(problem, twin, coils, found, count), twin, np.asarray(found.x, dtype=float), record
    )


def _distinct_starts(
    problem: DesignProblem,
    twin: DesignProblem,
    coils: list[HelicalCoilSpring],
    found: Solution,
    count: int,
    taken: np.ndarray | None = None,
) -> np.ndarray:
    """The twin's distinct feasible optima, best first (at most ``count``), each wound into coils (rows); none equal
    to ``taken`` (a twin design the coils start from already: the fitted one)."""
    if count < 1:
        return np.zeros((0, problem.variables.size))
    designs: list[np.ndarray] = []
    seen = [] if taken is None else [np.asarray(taken, dtype=float)]
    ranked = sorted((r for r in found.starts if r.feasible), key=lambda record: record.objective)
    for candidate in [np.asarray(found.x, dtype=float)] + [np.asarray(r.x, dtype=float) for r in ranked]:
        if len(designs) >= count:
            break
        if not any(np.allclose(candidate, design, rtol=1e-6, atol=1e-9) for design in designs + seen):
            designs.append(candidate)
    if not designs:
        return np.zeros((0, problem.variables.size))
    return np.array([_wound(problem, twin, coils, design) for design in designs])


def _fitted_twin(
    problem: DesignProblem, coils: list[HelicalCoilSpring], twin: DesignProblem, found: Solution, options: dict
) -> tuple[Solution, LinearRows | None] | None:
    """The twin fitted to the arm (:func:`~springbalance.design.clearance_starts.fit_from_starts`) and the rows of
    its fit (None when the design it kept was clear as it stood), or None when the fit does not converge. Its
    capsules are as wide as the widest coil's envelope (the twin's ideal springs have no coil of their own), so
    its rows hold for every coil that fits it; its rounds are solves of the ideal laws, far cheaper than the
    coils', each inside a trust region first (:func:`~springbalance.design.clearance_round.trust_rows`). When
    the twin's optimum was not clear as it stood, the rows also hold each spring on the side of each link the
    kept design passes on (:func:`~springbalance.design.clearance_sides.side_rows`)."""
    clearance = problem.clearance
    if clearance is not None:
        widest = max(_largest_outer_diameter(coil) for coil in coils)
        clearance = dataclasses.replace(clearance, radius=max(clearance.radius or DEFAULT_RADIUS, 0.5 * widest))
    wide = twin.with_springs(twin.springs, clearance=clearance)
    if wide.mounts:
        wide = wide.with_linear_rows(clearance_rows.mount_rows(wide, wide.variables.start))
    fit_options = {key: value for key, value in options.items() if key not in ("starts", "seed", "progress")}
    # each round inside a trust region first: the twin's zero-free-length-like laws let a round slide far
    solution, fit, fitted = clearance_starts.fit_from_starts(wide, found, trusted_first=True, **fit_options)
    if not fit.converged:
        return None
    if fit.rounds == 0:  # the twin's optimum was clear as it stood: the coils start there, free
        return solution, None
    # the fits moved the twin (or kept another design, clear as it stood): the coils keep the side of each link the
    # kept design passes on
    rows = stacked_rows(fitted.linear_rows, side_rows(wide, solution.x))
    if rows is None:
        return solution, None
    # the rows of the last round, linearised where it started: keep those the fitted design meets (a row it
    # breaks is stale, and with it the coils could meet no row set at all)
    held = clearance_rows.rows_held(wide, rows, solution.x)
    return None if held is None else (solution, held)


def _largest_outer_diameter(coil: HelicalCoilSpring) -> float:
    """The largest outer diameter [m] the coil's bounds allow: its envelope, else ``D + d`` at their upper bounds."""
    if coil.max_outer_diameter is not None:
        return float(coil.max_outer_diameter)
    return _bounds(coil, "mean_diameter")[1] + _bounds(coil, "wire_diameter")[1]


def _wound(problem: DesignProblem, twin: DesignProblem, coils: list[HelicalCoilSpring], x: np.ndarray) -> np.ndarray:
    """The design of ``problem`` with the anchors of the twin's design ``x`` and each coil wound for its law."""
    twin_values = dict(zip(twin.variables.names, x))
    start = dict(zip(problem.variables.names, problem.variables.start))
    start.update({name: value for name, value in twin_values.items() if name in start})
    evaluation = twin.evaluate(x)
    for column, spring in enumerate(twin.springs):
        if problem.springs[column] not in coils:
            continue
        coil = problem.springs[column]
        assert isinstance(coil, HelicalCoilSpring)  # one of `coils`
        law = twin.model.spring_values(spring, x)
        lengths, forces = evaluation.lengths[:, column], evaluation.tensions[:, column]
        start.update({f"{coil.name}.{key}": value for key, value in _wind(coil, law, lengths, forces).items()})
        floor = f"{coil.name}.{FLOOR}"  # a coil with a duty: its fatigue bounds at the twin's force range
        if floor in start and forces.size:
            start[floor], start[f"{coil.name}.{CEILING}"] = force_range(forces, coil.helical_kind)
    design = np.array([start[name] for name in problem.variables.names], dtype=float)
    lower, upper = problem.variables.bounds()
    return np.clip(design, lower, upper)


def _twin_problem(problem: DesignProblem, coils: list[HelicalCoilSpring], capped: bool = True) -> DesignProblem:
    """``problem`` with each of ``coils`` replaced by its ideal twin (:func:`_twin`), without
    ``no_joint_worse``."""
    twins = [_twin(spring, capped) if spring in coils else spring for spring in problem.springs]
    return problem.with_springs(twins, no_joint_worse=False)


def _ideal_record(
    problem: DesignProblem, coils: list[HelicalCoilSpring], twin: DesignProblem, found: Solution, options: dict
) -> TwinRecord:
    """The :class:`~springbalance.design.twin.TwinRecord` of the ideal twin: without the force cap of the
    first guess's twin (the reference a weak design is judged against is the law without the coil's
    limits), solved with the first guess's starts, its first from the capped optimum; that optimum's record when
    the uncapped solve fails. When the cap binds nowhere at the capped optimum (every twin's largest force
    below its cap), that optimum is a local optimum of the uncapped problem too, and its record is taken
    without solving again (the demo's twin balances exactly below its caps)."""
    source = ROUTED_TWIN_SOURCE if any(getattr(coil, "routed", False) for coil in coils) else TWIN_SOURCE
    ideal = _twin_problem(problem, coils, capped=False)
    if not _cap_binds(twin, np.asarray(found.x, dtype=float)):
        return twin_record(ideal, found.x, source)
    try:
        solved = solve_problem(ideal, **{**options, "initial": found.x, "progress": False})
    except SolverError:
        return twin_record(twin, found.x, source)
    return twin_record(ideal, solved.x, source)


def _cap_binds(twin: DesignProblem, x: np.ndarray) -> bool:
    """Whether some twin's largest force over the samples reaches its ``max_force`` (within
    :data:`CAP_SLACK` of it) at the design ``x``."""
    evaluation = twin.evaluate(x)
    for column, spring in enumerate(twin.springs):
        cap = getattr(spring, "max_force", None)
        if cap is not None and evaluation.tensions.shape[0]:
            if float(np.max(np.abs(evaluation.tensions[:, column]))) >= (1.0 - CAP_SLACK) * cap:
                return True
    return False


def _bounds(spring: Spring, key: str) -> tuple[float, float]:
    value = spring.parameters[key]
    return (float(value.lower), float(value.upper)) if isinstance(value, Free) else (float(value), float(value))


def _twin(coil: HelicalCoilSpring, capped: bool = True) -> ExtensionSpring | CompressionSpring:
    """The ideal law of the coil's kind, with the coil's anchors and limits, over generous ranges; a routed
    coil's twin keeps its pulleys and cable length (a twin between the path's ends alone removes nothing).
    ``capped``: an extension spring's force is at most what a coil within the bounds carries
    (:func:`_largest_force`)."""
    d_low, d_high = _bounds(coil, "wire_diameter")
    D_low, D_high = _bounds(coil, "mean_diameter")
    n_low, n_high = _bounds(coil, "active_coils")
    G = coil.material.shear_modulus
    stiffest = G * d_high**4 / (8 * max(D_low, coil.index_range[0] * d_high) ** 3 * n_low)  # [N/m]
    options = {key: getattr(coil, key) for key in ("max_force", "max_length", "min_length")}
    if getattr(coil, "routed", False):
        options.update(via=coil.via, cable_length=coil.parameters["cable_length"])
    if coil.kind == "extension":
        assert isinstance(coil, HelicalExtensionSpring)  # the helical law of kind "extension"
        force = _largest_force(coil) if capped else math.inf
        if force < math.inf and (options["max_force"] is None or options["max_force"] > force):
            options["max_force"] = force
        low, high = _bounds(coil, "initial_tension")
        shortest = d_low * (n_low + 1) + 2 * (coil.index_range[0] - 1) * d_low  # [m]
        longest = d_high * (n_high + 1) + 2 * (D_high - d_high)  # [m]
        return ExtensionSpring(
            coil.a,
            coil.b,
            coil.name,
            stiffness=Free(0.0, stiffest),
            free_length=Free(shortest, longest),
            initial_tension=Free(low, high),
            keep_tension=coil.keep_tension,
            **options,
        )
    assert isinstance(coil, HelicalCompressionSpring)  # the helical law of kind "compression"
    free_low, free_high = _bounds(coil, "free_length")
    return CompressionSpring(
        coil.a,
        coil.b,
        coil.name,
        stiffness=Free(0.0, stiffest),
        free_length=Free(free_low, free_high),
        preload=0.0,
        stays_compressed=coil.stays_compressed,
        **options,
    )


def _largest_force(coil: HelicalExtensionSpring) -> float:
    """The largest force [N] any coil within the bounds carries at its allowable body stress: the twin's limit,
    so that its law can be wound. The body stress is ``τ = K_B 8 F D/(π d³)`` (Shigley eq. 10-5); with
    ``D = C d``, ``F ≤ τ_a π d²/(8 K_B C)``, largest at the smallest index and the thickest wire that the
    envelope ``(C + 1) d ≤ OD`` and the bounds allow (inf when no wire fits)."""
    d_low, d_high = _bounds(coil, "wire_diameter")
    D_low, D_high = _bounds(coil, "mean_diameter")
    c_low, c_high = coil.index_range
    fraction = (1.0 - coil.stress_reserve) * coil.material.allowable_fraction[coil.helical_kind]
    largest = 0.0
    for d in [d for d in PREFERRED_WIRE_DIAMETERS if d_low <= d <= d_high] or [d_high]:
        index = max(c_low, D_low / d)
        if index > c_high or index * d > D_high:
            continue
        if coil.max_outer_diameter is not None and (index + 1) * d > coil.max_outer_diameter:
            continue
        bergstrasser = (4 * index + 2) / (4 * index - 3)
        strength = fraction * float(coil.material.tensile_strength(d))  # [Pa]
        largest = max(largest, strength * math.pi * d * d / (8 * bergstrasser * index))
    return largest if largest > 0 else math.inf


def _wind(coil: HelicalCoilSpring, law: dict, lengths: np.ndarray, forces: np.ndarray) -> dict[str, float]:
    """Wire, coil diameter and coils (and the initial tension) of a coil close to the ideal ``law``."""
    d_low, d_high = _bounds(coil, "wire_diameter")
    n_low, n_high = _bounds(coil, "active_coils")
    D_low, D_high = _bounds(coil, "mean_diameter")
    G = coil.material.shear_modulus
    rate = max(float(law["stiffness"]), 1e-9)  # [N/m]
    largest = float(np.max(np.abs(forces))) if forces.size else 0.0  # [N]
    wires = [d for d in PREFERRED_WIRE_DIAMETERS if d_low <= d <= d_high] or [0.5 * (d_low + d_high)]
    best, best_score = None, math.inf
    for d in wires:
        allowable = coil.material.allowable_fraction[coil.helical_kind] * float(coil.material.tensile_strength(d))
        for index in np.linspace(coil.index_range[0], coil.index_range[1], 17):
            D = index * d
            if not D_low <= D <= D_high or (coil.max_outer_diameter is not None and D + d > coil.max_outer_diameter):
                continue
            n = G * d**4 / (8 * D**3 * rate)
            if not n_low <= n <= n_high:
                continue
            if coil.kind == "extension":
                free = d * (n + 1) + 2 * (D - d)
                mismatch = abs(free - law["free_length"]) / max(law["free_length"], 1e-3)
            else:
                mismatch = max(0.0, d * (n + 2) - float(np.min(lengths))) / max(float(np.min(lengths)), 1e-3)
            stress = 8 * largest * D * (4 * index + 2) / ((4 * index - 3) * math.pi * d**3)  # K_B 8 F D/(π d³)
            score = mismatch + max(0.0, stress / allowable - 1.0)
            if score < best_score:
                best, best_score = (d, D, n), score
    if best is None:
        return {}
    d, D, n = best
    values = {"wire_diameter": d, "mean_diameter": D, "active_coils": n}
    if coil.kind == "extension":
        low, high = initial_stress_band(D / d)  # [Pa]
        to_force = math.pi * d**3 / (8 * D)  # [N/Pa]
        values["initial_tension"] = float(np.clip(law["initial_tension"], low * to_force, high * to_force))
    else:
        values["free_length"] = float(law["free_length"])
    return {key: value for key, value in values.items() if isinstance(coil.parameters.get(key), Free)}
