"""What flows through the solve pipeline: the options of a solve and the state between its steps.

:class:`SolveOptions` are the keyword arguments of :func:`springbalance.solve` (the same for every
step). :class:`SolveState` is what one step hands the next: the problem as the next step sees it
(with the linear rows that mounting and clearance add), the first guess, the solution so far and the
records of what each step did. A step is a function ``SolveState -> SolveState``; no step changes
the problem it is given (:meth:`~springbalance.design.problem.DesignProblem.with_linear_rows` makes
the next one).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping, Protocol

import numpy as np

from springbalance.design import clearance_starts, coil_start, standard_wire
from springbalance.design.clearance import FitRecord, LinearRows
from springbalance.design.joint_hold import JointHold
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution
from springbalance.design.standard_wire import WireRounding
from springbalance.design.twin import TwinRecord
from springbalance.design.verification_record import VerificationRecord
from springbalance.errors import InputError

#: the verification's default mode (:attr:`SolveOptions.verify`): "resolve" re-solves where a rule fails at
#: unseen poses (the demo's forearm coil went slack between its samples); "report" only reports
VERIFY_DEFAULT = "resolve"
#: the polish budget (:attr:`SolveOptions.polish_iterations`, as a multiple of ``max_iterations``) of a problem with
#: helical coils and no fit to the arm after its multi-start (:meth:`SolveOptions.for_problem`); the solvers' own
#: default is :data:`~springbalance.design.solvers.multistart.POLISH_FACTOR` (4). The coils' rules are nonlinear
#: rows that IPOPT closes in on slowly, and there the multi-start's best start is the design: bench_real's ur5-coils
#: at seed 1 stopped on the 4× budget at 0.468 N·m (93.16 % on the elbow, 1.95 points from the other seeds) and
#: reached 0.410 (94.93 %) with this one, the five seeds then within 0.49 point.
#: With a fit to the arm (clearance, mountings) its rounds re-solve the design, and a longer polish only moves where
#: they start: ur5-coils-clear at seed 3 went from 1.557 to 7.30 N·m with it, so it is not used there.
COIL_POLISH_FACTOR = 16
#: the polish budget (as a multiple of ``max_iterations``) of a problem with helical coils fitted to the arm: its
#: fitting rounds re-solve the design with the rows outside the multi-start's working set, and a polish there ends
#: where the plateau callback gives up on rows it does not see (:mod:`springbalance.design.plateau`): on
#: ur5-coils-clear (seed 0) both 400-iteration polishes gave up at iterations 142-181 and ended on their budget
#: outside 14-21 such rows, so neither design was kept. With 2× the five seeds ended at the same or lower
#: objectives (seed 0: 0.777 N·m instead of 0.893) in no more time (docs/developer/performance.md, session 48).
FITTED_COIL_POLISH_FACTOR = 2


class ConfiguredProblem(Protocol):
    """A problem with the solve options its source gave (a :class:`springbalance.io.config.Config`)."""

    problem: DesignProblem
    solve_options: Mapping[str, Any]


@dataclasses.dataclass(frozen=True)
class SolveOptions:
    """How to solve (see :func:`springbalance.solve` for each option).

    Attributes:
        starts: number of starts: the user's initial guess, then scrambled Sobol points of the bounds.
        seed: seed of the start points (the result is deterministic given it).
        method: ``"auto"``, ``"least_squares"`` or ``"ipopt"``.
        progress: show a progress bar (None: when more than one start and stderr is a terminal).
        max_iterations: iteration limit per start and phase (the screening budget).
        tolerance: relative cost change at which least squares stop.
        polish_iterations: further iterations for the best starts stopped by the limit (None: 4 × max_iterations;
            :data:`COIL_POLISH_FACTOR` × for coils not fitted to the arm, :data:`FITTED_COIL_POLISH_FACTOR` × for
            coils fitted to it, :meth:`for_problem`).
        standard_wire: round every coil's free wire diameter to the standard sizes (``wire_sizes``).
        wire_sizes: the wire diameters [m] the spring maker draws, sorted: what the rounding rounds to and what the
            report judges a wire against (None: the preferred series,
            :data:`~springbalance.springs.sizing.PREFERRED_WIRE_DIAMETERS`).
        workers: processes that run the starts at once (None: ``$SPRINGBALANCE_WORKERS`` or the cores).
        verify: what the verification at unseen poses does when a rule fails there: ``"resolve"`` (add the
            worst poses as samples and solve again), ``"report"`` (report only) or ``"off"`` (no verification);
            :mod:`springbalance.design.verification_loop`.
        seeds: solve at each of these seeds and keep the best design (:mod:`springbalance.results.seed_search`),
            or None: solve at ``seed`` alone.
    """

    starts: int = 8
    seed: int = 0
    method: str = "auto"
    progress: bool | None = None
    max_iterations: int = 100
    tolerance: float = 1e-8
    polish_iterations: int | None = None
    standard_wire: bool = True
    wire_sizes: tuple[float, ...] | None = None
    workers: int | None = None
    verify: str = VERIFY_DEFAULT
    seeds: tuple[int, ...] | None = None

    @classmethod
    def merged(cls, given: Mapping[str, Any], overrides: Mapping[str, Any]) -> SolveOptions:
        """The options of ``given`` (a config's ``solve`` section) overridden by the ``overrides`` that are
        not None; the rest take the defaults above. ``seed`` and ``seeds`` exclude each other: given together in
        either, an InputError; a ``seed`` override drops the ``seeds`` given, and a ``seeds`` override the ``seed``."""
        names = {field.name for field in dataclasses.fields(cls)}
        chosen = {key: value for key, value in overrides.items() if value is not None}
        for source, where in ((given, "solve section"), (chosen, "options")):
            if "seed" in source and "seeds" in source:
                raise InputError(f"{where}: both seed and seeds given; give one seed, or the seeds to keep the best of")
        options = {**given, **chosen}
        if "seed" in chosen:  # one seed asked for wins over the seeds given, and the other way round
            options.pop("seeds", None)
        elif "seeds" in chosen:
            options.pop("seed", None)
        unknown = sorted(set(options) - names)
        if unknown:
            raise InputError(
                f"unknown solve option(s) {', '.join(map(repr, unknown))}; valid: {', '.join(sorted(names))}"
            )
        if options.get("seeds") is not None:
            options["seeds"] = checked_seeds(options["seeds"])
        if options.get("wire_sizes") is not None:
            options["wire_sizes"] = standard_wire.checked_wire_sizes(options["wire_sizes"])
        return cls(**options)

    def for_problem(self, problem: DesignProblem) -> SolveOptions:
        """These options with the polish budget ``problem`` needs, unless ``polish_iterations`` was given: for a
        problem with free helical coils, :data:`COIL_POLISH_FACTOR` × ``max_iterations`` when it is not fitted to the
        arm (no clearance, no mountings), :data:`FITTED_COIL_POLISH_FACTOR` × when it is; otherwise these options."""
        if self.polish_iterations is not None or not coil_start.coil_springs(problem):
            return self
        factor = FITTED_COIL_POLISH_FACTOR if clearance_starts.fitted_to_arm(problem) else COIL_POLISH_FACTOR
        return dataclasses.replace(self, polish_iterations=factor * self.max_iterations)

    def solver_options(self) -> dict[str, Any]:
        """The options every solve of the pipeline passes on: method, iteration limits, tolerance."""
        return {
            "method": self.method,
            "max_iterations": self.max_iterations,
            "tolerance": self.tolerance,
            "polish_iterations": self.polish_iterations,
        }


@dataclasses.dataclass(frozen=True)
class SolveState:
    """The state between two steps of the pipeline.

    Attributes:
        problem: the problem the next step solves (the caller's, or a copy with linear rows).
        options: the solve's options.
        initial: the first start (physical units), or None for the problem's own first guess.
        solution: the best design so far (None before the multi-start).
        fit: what fitting the springs to the arm did (None when not asked for).
        wire_rounding: what rounding the coils' wires cost (None when nothing was rounded).
        joint_hold: what holding the joints within the bare arm's peaks did (None when no weighted joint was
            carried worse).
        verification: what verifying the design at unseen poses found (None when not verified).
        twin: what the ideal twin achieved (the coils' ideal twin, else the optimum before the fit to the
            arm; None for a problem that has neither coils nor clearance or mountings).
        kept_rows: the rows of the ideal twin's fit to the arm, which the coils keep (None without one).
    """

    problem: DesignProblem
    options: SolveOptions
    initial: np.ndarray | None = None
    solution: Solution | None = None
    fit: FitRecord | None = None
    wire_rounding: WireRounding | None = None
    joint_hold: JointHold | None = None
    verification: VerificationRecord | None = None
    twin: TwinRecord | None = None
    kept_rows: LinearRows | None = None

    @property
    def solved(self) -> Solution:
        """The solution so far (the steps after the multi-start have one)."""
        if self.solution is None:
            raise RuntimeError("no solution yet: the multi-start step runs before this one")
        return self.solution

    def but(self, **changes: Any) -> SolveState:
        """This state with ``changes`` (a step's output)."""
        return dataclasses.replace(self, **changes)


def checked_seeds(seeds: Any, label: str = "seeds") -> tuple[int, ...]:
    """``seeds`` as a tuple of distinct integers ≥ 0, in order; InputError naming ``label`` and the value otherwise."""
    if isinstance(seeds, (str, bytes)) or not hasattr(seeds, "__iter__"):
        raise InputError(f"{label} must be a list of integers >= 0, got {seeds!r}")
    values = list(seeds)
    if not values or any(isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0 for v in values):
        raise InputError(f"{label} must be a non-empty list of integers >= 0, got {values!r}")
    if len(set(values)) != len(values):
        raise InputError(f"{label} must be distinct, got {values!r}")
    return tuple(int(v) for v in values)
