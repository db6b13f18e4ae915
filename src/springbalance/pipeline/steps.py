"""The steps of a solve, in the order :func:`springbalance.solve` runs them (:data:`STEPS`).

Each step is a function ``SolveState -> SolveState`` that does nothing when its part of the problem
is absent:

1. :func:`first_guess`: helical coils start from the ideal twin's optima, wound into coils
   (:mod:`springbalance.design.coil_start`); the twin's record (:mod:`springbalance.design.twin`) is kept;
2. :func:`mount_rows`: anchors mounted ``on: collision`` start on their surface planes, linearised where the
   optimum without them puts them (:func:`free_optimum`; :mod:`springbalance.design.clearance_rows`);
3. :func:`multi_start`: every start, then the polish of the best (:mod:`springbalance.design.solvers`);
4. :func:`fit_to_arm`: clearance from the links and mountings, by linearised rows refreshed until a
   check finds no violation (:mod:`springbalance.design.clearance_fit`, the fits side by side:
   :mod:`springbalance.design.clearance_starts`); without a coil twin, the
   multi-start's optimum before the fit is the twin;
5. :func:`round_wires`: every coil's free wire to the preferred series, the rest re-optimised
   (:mod:`springbalance.design.standard_wire`);
6. :func:`hold_joints`: a design that carries a weighted joint worse than the bare arm is solved again from
   itself with every weighted joint held within the bare arm's peak, the wires held
   (:mod:`springbalance.design.joint_hold`);
7. :func:`verify`: every rule, the residual and the clearance at 10× as many unseen poses; where a rule
   fails, the worst poses join the samples and the design is solved again (mode ``"resolve"``)
   (:mod:`springbalance.design.verification_loop`).

Stock selection, when asked for, follows on the finished design (:mod:`springbalance.pipeline.stock`).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from springbalance.design import (
    clearance_rows,
    clearance_starts,
    coil_start,
    joint_hold,
    standard_wire,
    verification_loop,
)
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution, solve_problem
from springbalance.design.twin import twin_record
from springbalance.errors import Interrupted, SolverError
from springbalance.pipeline.state import SolveState

#: the progress bar of the multi-start without the mountings (:func:`free_optimum`)
FREE_OPTIMUM_LABEL = "starts, anchors off their surfaces"
#: what the twin of a problem fitted to the arm is (without coils), in the words of its record
FIT_TWIN_SOURCE = "the multi-start's optimum before the fit to the arm (no clearance rows)"


def first_guess(state: SolveState) -> SolveState:
    """Coils: the first starts from the ideal twin's distinct optima, wound into coils, and the twin's record
    (nothing when the twin fails)."""
    problem, options = state.problem, state.options
    if not coil_start.coil_springs(problem):
        return state
    try:
        start = coil_start.coil_starts(
            problem,
            options.starts,
            starts=options.starts,
            seed=options.seed,
            method=options.method,
            max_iterations=options.max_iterations,
            tolerance=options.tolerance,
        )
    except Interrupted:  # the ideal twin's starts are not designs of this problem
        raise Interrupted(
            "interrupted while finding the coils' first guess: no start of the design had "
            f"finished (0 of {options.starts})",
            problem=problem,
            total=options.starts,
        ) from None
    if start is None:
        return state
    if start.rows is None:
        return state.but(initial=start.starts, twin=start.record)
    # the twin was fitted to the arm: the coils start from its fitted design, inside its rows
    rows = start.rows
    return state.but(initial=start.starts, twin=start.record, problem=problem.with_linear_rows(rows), kept_rows=rows)


def mount_rows(state: SolveState) -> SolveState:
    """Mounted anchors: the rows that hold them on their surfaces, linearised where the optimum without them puts
    them (:func:`free_optimum`), else at the problem's first guess."""
    problem = state.problem
    if not problem.mounts or state.kept_rows is not None:  # (the twin's fit holds them already)
        return state
    at = free_optimum(state)
    if at is None:
        at = np.asarray(problem.variables.start, dtype=float)
    return state.but(problem=problem.with_linear_rows(clearance_rows.mount_rows(problem, at)))


def free_optimum(state: SolveState) -> np.ndarray | None:
    """The multi-start's optimum of the problem without its mounting rows (anchors anywhere in their boxes), None
    when no start is feasible. A mounting row is the tangent plane of the anchor's offset surface at the point
    closest to where it is linearised: at the box's centre, every start keeps each anchor on one plane there,
    however far the surface curves away from it (the UR5 with six anchors on its links: the multi-start's optima
    at 8.4-14.9 N·m, left to a dozen fitting rounds, 3 of 5 seeds NOT converged); at the free optimum's anchors,
    projected onto their surfaces, the planes lie where a good design has them (0.46-1.65 N·m, every seed fitted
    in 10-24 rounds over two fits, converged)."""
    options = state.options
    try:
        solution = _multi_started(state, state.problem, state.options.progress, FREE_OPTIMUM_LABEL)
    except SolverError:
        return None
    except Interrupted:
        raise Interrupted(
            "interrupted while solving without the mountings (where their rows are linearised): no start of the "
            f"design had finished (0 of {options.starts})",
            problem=state.problem,
            total=options.starts,
        ) from None
    return np.asarray(solution.x, dtype=float)


def multi_start(state: SolveState) -> SolveState:
    """Every start, screened then polished; the best feasible design (SolverError when none is). When no coil
    start meets the rows of the twin's fit, the starts run again without them (the fit to the arm then finds
    its own)."""
    progress = state.options.progress
    try:
        return state.but(solution=_multi_started(state, state.problem, progress))
    except SolverError:
        if state.kept_rows is None:
            raise
    problem = state.problem.with_linear_rows(None)
    return state.but(problem=problem, solution=_multi_started(state, problem, progress), kept_rows=None)


def _multi_started(state: SolveState, problem: DesignProblem, progress: bool | None, label: str = "starts") -> Solution:
    """The multi-start of ``problem`` with the solve's options (starts, seed, solver) from the state's first
    starts; ``label``: its progress bar's."""
    options = state.options
    return solve_problem(
        problem,
        starts=options.starts,
        seed=options.seed,
        progress=progress,
        initial=state.initial,
        label=label,
        **options.solver_options(),
    )


def tightened(problem: DesignProblem) -> bool:
    """Whether the fit to the arm tightens its fitted designs
    (:class:`~springbalance.design.clearance_round.Tightening`): without free helical coils. With them, on
    bench_real's UR5 with three coils on its links' surfaces, tightened fits moved the designs where rounding the
    wires then made the elbow's peak worse than the bare arm's at two of five seeds (exit 3; they passed
    untightened), and ur5-coils-clear's 4× search failed its verification at unseen poses."""
    return not coil_start.coil_springs(problem)


def thin_first(problem: DesignProblem) -> bool:
    """Whether the fit to the arm starts from a fit of the springs as thin lines
    (:func:`~springbalance.design.clearance_starts.fit_thin_first`): with a clearance and without free helical coils,
    whose capsules are their own coils' (a thin stage would be the same fit again)."""
    return problem.clearance is not None and tightened(problem)


def fit_to_arm(state: SolveState) -> SolveState:
    """Clearance and mountings: the fitted design and the problem with its final rows."""
    problem = state.problem
    if not clearance_starts.fitted_to_arm(problem):
        return state
    twin = state.twin or twin_record(problem, state.solved.x, FIT_TWIN_SOURCE)
    with _interrupted_after_starts(state, "fitting the springs to the arm"):
        solution, fit, problem = clearance_starts.fit_from_starts(
            problem,
            state.solved,
            state.kept_rows,
            tighten=tightened(problem),
            verify=verification_loop.check_mode(state.options.verify),
            thin_first=thin_first(problem),
            **state.options.solver_options(),
        )
    return state.but(problem=problem, solution=solution, fit=fit, twin=twin)


def round_wires(state: SolveState) -> SolveState:
    """Coils with a free wire: standard wire sizes (the options' ``wire_sizes``), the rest re-optimised."""
    if not state.options.standard_wire or not standard_wire.coils_with_free_wire(state.problem):
        return state
    with _interrupted_after_starts(state, "rounding the wires"):
        solution, rounding = standard_wire.round_wires(
            state.problem, state.solved, state.options.wire_sizes, **state.options.solver_options()
        )
    return state.but(solution=solution, wire_rounding=rounding)


def hold_joints(state: SolveState) -> SolveState:
    """A design that carries a weighted joint worse than the bare arm: solved again from itself with every weighted
    joint held within the bare arm's peak, the rounded wires held, and kept when it makes no weighted joint worse
    (:func:`~springbalance.design.joint_hold.held_within_bare_arm`); what that did is the state's ``joint_hold``."""
    with _interrupted_after_starts(state, "holding the joints within the bare arm's peaks"):
        solution, hold = joint_hold.held_within_bare_arm(
            state.problem, state.solved, fixed=_rounded_wires(state), **state.options.solver_options()
        )
    return state.but(solution=solution, joint_hold=hold)


def verify(state: SolveState) -> SolveState:
    """The design at unseen poses: its record, and in mode "resolve" the design re-solved where a rule fails (with
    the joints held within the bare arm's peaks when :func:`hold_joints` held them)."""
    mode = verification_loop.check_mode(state.options.verify)
    if mode == "off":
        return state
    held = state.joint_hold is not None and state.joint_hold.held  # (its re-solves keep the joints held)
    with _interrupted_after_starts(state, "verifying the design at unseen poses"):
        solution, record, problem = verification_loop.verify_and_resolve(
            state.problem, state.solved, mode, _rounded_wires(state), held, **state.options.solver_options()
        )
    return state.but(problem=problem, solution=solution, verification=record)


def _rounded_wires(state: SolveState) -> list[str]:
    """The design variables of the wires rounded to standard sizes (held by the steps after the rounding)."""
    rounded = state.wire_rounding.wires if state.wire_rounding is not None else {}
    return [f"{name}.{standard_wire.WIRE}" for name in rounded]


class _interrupted_after_starts:
    """Ctrl-C after the multi-start: its best design (or the last fitted one) is the best so far."""

    def __init__(self, state: SolveState, phase: str) -> None:
        self.state, self.phase = state, phase

    def __enter__(self) -> None:
        return None

    def __exit__(self, kind: type | None, error: BaseException | None, traceback: object) -> None:
        if isinstance(error, Interrupted):
            solution = self.state.solved
            raise Interrupted(
                f"interrupted while {self.phase}: all {len(solution.starts)} starts had finished",
                problem=self.state.problem,
                starts=solution.starts,
                total=len(solution.starts),
                best_x=solution.x,
            ) from None


#: The solve, step by step.
STEPS: tuple[Callable[[SolveState], SolveState], ...] = (
    first_guess,
    mount_rows,
    multi_start,
    fit_to_arm,
    round_wires,
    hold_joints,
    verify,
)
