"""``springbalance.solve``: the one entry point from a problem (or a config) to a design.

.. code-block:: python

    result = sb.solve(problem, starts=8)            # a DesignProblem
    result = sb.solve(load_config("arm.yaml"))      # or a Config: its ``solve:`` section gives the defaults

The sequence is :data:`springbalance.pipeline.steps.STEPS` (first guess → mounting rows → multi-start
→ fit to the arm → standard wires → verification), then, with ``stock``, the choice of catalogue parts
(:func:`springbalance.pipeline.stock.select_stock`). Each step takes the state the previous one made
and gives the next; the problem passed in is never changed.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from typing import Sequence

from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import Solution
from springbalance.design.stock import StockPart, StockSelection
from springbalance.design.twin import twin_record
from springbalance.design.verification_loop import check_mode, verify_and_resolve
from springbalance.design.verification_record import VerificationRecord
from springbalance.errors import InputError, Interrupted, SolverError
from springbalance.pipeline.sequence import run_steps
from springbalance.pipeline.state import ConfiguredProblem, SolveOptions
from springbalance.pipeline.stock import select_stock
from springbalance.results.result import DesignResult
from springbalance.results.seed_search import SeedRun, SeedSearch

#: what the twin of a stock design is (without coils or a fit to the arm), in the words of its record
STOCK_TWIN_SOURCE = "the continuous design before the stock parts were chosen"
#: starts of each stock candidate's solve: the warm start at the continuous design plus one Sobol start
STOCK_STARTS = 2


def solve(
    problem_or_config: DesignProblem | ConfiguredProblem,
    *,
    starts: int | None = None,
    seed: int | None = None,
    method: str | None = None,
    progress: bool | None = None,
    max_iterations: int | None = None,
    tolerance: float | None = None,
    polish_iterations: int | None = None,
    standard_wire: bool | None = None,
    wire_sizes: Sequence[float] | None = None,
    workers: int | None = None,
    stock: Sequence[StockPart] | None = None,
    verify: str | None = None,
    seeds: Sequence[int] | None = None,
) -> DesignResult:
    """Design the springs: the best feasible design of a multi-start solve, as a :class:`DesignResult`.

    Args:
        problem_or_config: a :class:`~springbalance.design.problem.DesignProblem`, or a
            :class:`~springbalance.io.config.Config`, whose ``solve`` section gives the defaults of the
            options below (an option given here wins).
        starts: number of starts: the user's initial guess, then scrambled Sobol points of the bounds (8).
        seed: seed of the start points; the result is deterministic given it (0).
        method: ``"auto"`` (least squares where the objective has that structure, IPOPT where it does not or
            where constraints bind), ``"least_squares"`` or ``"ipopt"``.
        progress: show a progress bar (default: when more than one start and stderr is a terminal).
        max_iterations: iteration limit per start and phase, the screening budget (100).
        tolerance: least squares stop when a step lowers the cost by less than this fraction (1e-8); IPOPT's
            own tolerance is min(tolerance, 1e-8).
        polish_iterations: further iterations for the best starts when they stopped on the limit, and for
            the least violated ones when no start is feasible (default 4 × max_iterations; with free helical
            coils 16× without a fit to the arm and 2× with one; 0 disables).
        standard_wire: round every helical spring's free wire diameter to the standard sizes (``wire_sizes``)
            and re-optimise the rest (True); the result's ``wire_rounding`` says what it cost.
        wire_sizes: the wire diameters [m] your spring maker draws: the sizes the wires are rounded to and that
            the report judges each coil's wire against (``off_series_wire``); kept as the result's ``wire_sizes``.
            Default: a Config's ``solve.wire_sizes``, else the preferred metric series
            (:data:`~springbalance.springs.sizing.PREFERRED_WIRE_DIAMETERS`).
        workers: processes that run the starts (and polish runs) at once; the design does not depend on it.
            Default: ``$SPRINGBALANCE_WORKERS``, else ``os.cpu_count()`` (1 for a small problem).
        stock: stock parts (:func:`springbalance.load_stock`: ``sb.load_stock("ms24586")``, the standard
            catalogues or a CSV file): each extension and compression spring is then replaced by its
            nearest part and the rest re-optimised; the result's ``stock`` is the
            :class:`~springbalance.design.stock.StockSelection`. Default: a Config's ``solve.stock``, else none.
        verify: the verification at 10× as many unseen poses (:mod:`springbalance.design.verification`):
            ``"resolve"`` (the default, :data:`~springbalance.pipeline.state.VERIFY_DEFAULT`) re-solves with the
            worst poses added where a rule fails there, ``"report"`` only reports, ``"off"`` skips it.
            The result's ``verification`` is its record (of the stock design, reported only, with ``stock``).
        seeds: solve at each of these seeds (instead of ``seed``) and keep the best design: the first that passes
            every check, by objective (:mod:`springbalance.results.seed_search`); the result's ``seed_search``
            says what each seed gave; with a progress bar, each seed is announced on stderr before its bars
            ("seed 2 (3 of 5)"). Default: a Config's ``solve.seeds``, else one seed. ``seed`` and ``seeds``
            exclude each other; either one given here overrides the other in a Config.

    Returns:
        The design, also when it fails a check (an unconverged fit to the arm, a spring overlapping a
        link, a coil that cannot be wound, ...): ``result.ok`` is then False and ``result.failures()``
        says why (:mod:`springbalance.results.flags`). Its ``twin`` records what the ideal twin achieved.

    Raises:
        SolverError: no start gives a feasible design (or no stock part fits a spring).
        Interrupted: Ctrl-C; it carries the starts that had finished and the best design so far.
    """
    stock = getattr(problem_or_config, "stock", None) if stock is None else stock  # default: a Config's solve.stock
    problem, given = _problem_and_options(problem_or_config, stock)
    options = SolveOptions.merged(
        given,
        {
            "starts": starts,
            "seed": seed,
            "method": method,
            "progress": progress,
            "max_iterations": max_iterations,
            "tolerance": tolerance,
            "polish_iterations": polish_iterations,
            "standard_wire": standard_wire,
            "wire_sizes": wire_sizes,
            "workers": workers,
            "verify": verify,
            "seeds": seeds,
        },
    )
    if options.seeds is not None:
        result, kept = _best_of_seeds(problem, options)
        options = dataclasses.replace(options, seed=kept, seeds=None)  # the stock parts' solves at the kept seed
    else:
        result = run_steps(problem, options)
    result.tolerance = getattr(problem_or_config, "tolerance", None)  # a config's tolerance section
    result.wire_sizes = options.wire_sizes
    if stock is None:
        return result
    # the problem as the steps left it (with the rows of the fit), as the parts are fitted to the arm the same way
    stocked = _stocked(result, _select_stock(result.problem, result, stock, options), options)
    stocked.seed_search = result.seed_search  # the seeds of the continuous design the parts replace
    stocked.wire_sizes = options.wire_sizes
    return stocked


def _best_of_seeds(problem: DesignProblem, options: SolveOptions) -> tuple[DesignResult, int]:
    """The design of ``problem`` solved at each of ``options.seeds``, the best kept
    (:func:`~springbalance.results.seed_search.best_run`), with its ``seed_search``, and its seed; SolverError when
    no seed found a design."""
    assert options.seeds is not None  # the caller's condition
    runs: list[SeedRun] = []
    best: tuple[SeedRun, DesignResult] | None = None
    shown = options.progress if options.progress is not None else sys.stderr.isatty()  # as the starts' bars are
    for number, seed in enumerate(options.seeds, 1):
        if shown:  # which seed the bars below belong to
            print(f"seed {seed} ({number} of {len(options.seeds)})", file=sys.stderr, flush=True)
        clock = time.perf_counter()
        try:
            result = run_steps(problem, dataclasses.replace(options, seed=seed, seeds=None))
        except SolverError as error:
            runs.append(SeedRun(seed, None, seconds=time.perf_counter() - clock, error=str(error)))
            continue
        except Interrupted as stop:
            raise _interrupted_at(stop, seed, len(runs), len(options.seeds), best) from None
        kinds = tuple(dict.fromkeys(flag.kind for flag in result.failures()))
        run = SeedRun(seed, result.problem.objective_at(result.x), kinds, time.perf_counter() - clock)
        runs.append(run)
        if best is None or run.rank() < best[0].rank():  # best_run's order as the seeds come; one design in memory
            best = (run, result)
    if best is None:
        raise SolverError("no seed gave a feasible design: " + "; ".join(f"seed {r.seed}: {r.error}" for r in runs))
    best[1].seed_search = SeedSearch(tuple(runs), best[0].seed)
    return best[1], best[0].seed


def _interrupted_at(
    stop: Interrupted, seed: int, finished: int, total: int, best: tuple[SeedRun, DesignResult] | None
) -> Interrupted:
    """Ctrl-C while solving at ``seed``: ``stop`` itself when no seed had finished with a design, else the
    interruption with the best finished seed's design as the best so far."""
    if best is None:
        return stop
    run, result = best
    return Interrupted(
        f"interrupted at seed {seed} ({finished} of {total} seeds finished, the design of seed {run.seed} the best)",
        problem=result.problem,
        starts=result.starts,
        total=len(result.starts),
        best_x=result.x,
    )


def _stocked(result: DesignResult, selection: StockSelection, options: SolveOptions) -> DesignResult:
    """The stock design of ``selection`` for the continuous design ``result``; its twin is ``result``'s
    ideal twin, else the continuous design that the parts replace."""
    stocked = selection.result
    return DesignResult(
        stocked.problem,
        stocked.x,
        starts=stocked.starts,
        method=stocked.method,
        seed=stocked.seed,
        status=stocked.status,
        wire_rounding=stocked.wire_rounding,
        fit=stocked.fit,
        stock=selection,
        verification=_verified(stocked, options),
        twin=result.twin or twin_record(result.problem, result.x, STOCK_TWIN_SOURCE),
        tolerance=result.tolerance,
    )


def _verified(result: DesignResult, options: SolveOptions) -> VerificationRecord | None:
    """The verification of a finished design at unseen poses, reported only (None when it is off)."""
    if check_mode(options.verify) == "off":
        return None
    solution = Solution(result.x, result.starts, result.method, result.seed or 0, result.status)
    return verify_and_resolve(result.problem, solution, "report")[1]


def _problem_and_options(
    source: DesignProblem | ConfiguredProblem, stock: Sequence[StockPart] | None = None
) -> tuple[DesignProblem, dict]:
    """The problem and the options its source gave (none for a bare problem); InputError for stock parts
    with a robust design (a part's law is fixed, so it has no corners to design for)."""
    problem = source if isinstance(source, DesignProblem) else getattr(source, "problem", None)
    if not isinstance(problem, DesignProblem):
        raise InputError(f"springbalance.solve takes a DesignProblem or a Config, got {type(source).__name__}")
    if stock is not None and problem.corners is not None:
        raise InputError(
            "tolerance.robust: stock parts cannot be chosen for a robust design (a part's law is fixed); "
            "solve without --stock, or without robust"
        )
    return problem, ({} if source is problem else dict(getattr(source, "solve_options", None) or {}))


def _select_stock(
    problem: DesignProblem, result: DesignResult, parts: Sequence[StockPart], options: SolveOptions
) -> StockSelection:
    """Catalogue parts for the continuous design ``result``; each candidate part is solved from the warm
    start at the continuous anchors plus one Sobol start; the chosen parts are checked under the design's tolerances."""
    return select_stock(
        problem,
        result,
        parts,
        starts=min(options.starts, STOCK_STARTS),
        seed=options.seed,
        method=options.method,
        max_iterations=options.max_iterations,
        tolerance=options.tolerance,
        workers=options.workers,
        tolerances=result.tolerance,
    )
