"""IPOPT's derivatives through the per-sample structure (design/structured_nlp.py) equal CasADi's
own derivatives of the plain NLP, and the working set of rows ends at a solution of the full NLP."""

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
import yaml

import springbalance as sb
from springbalance.design.structured_nlp import StructuredNlp
from springbalance.io.config import config_from_dict, load_config


def _planar(objective, samples=96):
    mechanism = sb.Mechanism.from_urdf("urdf/two_link_planar.urdf")
    workspace = sb.Workspace.sobol(mechanism, samples, seed=2)
    springs = [
        sb.ExtensionSpring(
            sb.Anchor("universe", sb.Free([-0.1, 0, 0.05], [0.1, 0, 0.3])),
            sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.5, 0, 0])),
            "shoulder",
            stiffness=sb.Free(0, 3000),
            free_length=sb.Free(0.02, 0.3),
        ),
        sb.ExtensionSpring(
            sb.Anchor("link1", sb.Free([0.1, 0, -0.05], [0.5, 0, 0.05])),
            sb.Anchor("link2", sb.Free([-0.15, 0, -0.05], [0.4, 0, 0.05])),
            "elbow",
            stiffness=sb.Free(0, 3000),
            free_length=sb.Free(0.02, 0.3),
        ),
    ]
    return sb.DesignProblem(mechanism, workspace, springs, objective=objective)


def _coils():
    return load_config("examples/two_link.yaml").problem


def _static_coils():
    """The demo's coils with the static rules only (no ``duty``: no fatigue floor variable)."""
    record = yaml.safe_load(open("examples/two_link.yaml", encoding="utf-8"))
    for spring in record["springs"]:
        spring.pop("duty", None)
    return config_from_dict(record, base_dir=Path("examples")).problem


def _dense(value):
    return np.array(ca.densify(value))


@pytest.mark.parametrize(
    "make",
    [lambda: _planar("peak"), lambda: _planar("joint_peaks"), lambda: _planar("rms"), _coils],
    ids=["peak", "joint_peaks", "rms", "coil-rows"],
)
def test_derivatives_equal_casadi_of_the_plain_nlp(make):
    problem = make()
    structured = StructuredNlp(problem)
    x, _, _, derivatives = structured.callbacks(np.arange(structured.n_rows))
    plain = problem.build()
    solver = ca.nlpsol(
        "plain",
        "ipopt",
        {"x": plain.z, "f": plain.cost, "g": plain.rows},
        {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes"},
    )
    rng = np.random.default_rng(7)
    point, multipliers = rng.random(plain.size), rng.normal(size=plain.n_rows)
    for name, ours, arguments in (
        ("nlp_grad_f", derivatives["grad_f"], (point, [])),
        ("nlp_jac_g", derivatives["jac_g"], (point, [])),
        ("nlp_hess_l", derivatives["hess_lag"], (point, [], 0.8, multipliers)),
    ):
        theirs = solver.get_function(name)(*arguments)
        mine = ours(*arguments)
        theirs, mine = ([theirs], [mine]) if name == "nlp_hess_l" else (theirs, mine)
        for a, b in zip(theirs, mine):
            a, b = _dense(a), _dense(b)
            assert a.shape == b.shape, name
            assert np.allclose(a, b, rtol=1e-10, atol=1e-12 * max(1.0, np.max(np.abs(a)))), name


@pytest.mark.parametrize("constant", [True, False], ids=["constant-row-jacobians", "scalar-graph"])
@pytest.mark.parametrize("make", [lambda: _planar("rms"), _coils], ids=["rms", "coil-rows"])
def test_derivatives_on_a_working_set_equal_casadi_of_the_plain_nlp(make, constant):
    """On a part of the rows, whose samples are fewer than the cost's (rms uses every sample), the rows and their
    Jacobian come from those samples alone and still equal CasADi's derivatives of the plain NLP's same rows: from
    the affine rows' constant Jacobians, and through CasADi's scalar graph (the way of rows that are not affine)."""
    problem = make()
    structured = StructuredNlp(problem)
    assert structured._row_jacobians is not None  # these rows are affine in the outputs and the variables
    if not constant:
        structured._row_jacobians = None
    every = np.arange(structured.n_rows)
    rows = every[(every % 3 == 1) & (structured._row_sample < structured.n_samples // 2)]
    x, _, constraints, derivatives = structured.callbacks(rows)
    assert structured._restricted(rows).row_samples.size < structured._restricted(rows).samples.size
    plain = problem.build()
    rng = np.random.default_rng(11)
    point, multipliers = rng.random(plain.size), rng.normal(size=rows.size)
    g_rows = plain.rows[rows.tolist()]
    theirs_jacobian = ca.Function("j", [plain.z], [g_rows, ca.jacobian(g_rows, plain.z)])(point)
    mine_jacobian = derivatives["jac_g"](point, [])
    lagrangian = 0.8 * plain.cost + ca.dot(multipliers, g_rows)
    theirs_hessian = ca.Function("h", [plain.z], [ca.triu(ca.hessian(lagrangian, plain.z)[0])])(point)
    mine_hessian = derivatives["hess_lag"](point, [], 0.8, multipliers)
    mine_rows = ca.Function("g", [x], [constraints])(point)
    for a, b in zip([*theirs_jacobian, theirs_hessian, theirs_jacobian[0]], [*mine_jacobian, mine_hessian, mine_rows]):
        a, b = _dense(a), _dense(b)
        assert a.shape == b.shape
        assert np.allclose(a, b, rtol=1e-10, atol=1e-12 * max(1.0, np.max(np.abs(a))))


def test_working_set_ends_at_a_solution_of_the_full_nlp():
    """From the rms design, a peak solve sees a part of the 2·N·nv rows, yet every row holds at its answer
    and IPOPT on all rows, started there, finds nothing lower."""
    problem = _planar("peak", samples=512)
    rms = _planar("rms", samples=512)
    start = sb.solve(rms, starts=1, workers=1).x
    structured = StructuredNlp(problem)
    nlp = structured.nlp
    evaluation = problem.evaluate(start)
    w0 = np.concatenate([np.clip(problem.unscale(start), 0, 1), nlp.extra_start(evaluation.tau * problem.weights)])
    seen = []
    original = structured._solver

    def counting(rows, options):
        seen.append(rows.size)
        return original(rows, options)

    structured._solver = counting
    options = {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes", "ipopt.tol": 1e-8}
    w, status, iterations, _ = structured.solve(w0, nlp.lower, nlp.upper, options, 200)
    assert status == "Solve_Succeeded"
    assert max(seen) < nlp.n_rows / 2  # IPOPT never had most of the rows
    assert np.min(structured.row_values(w)) > -1e-7
    peak = problem.objective_value(problem.evaluate(problem.scale(w[: nlp.n_design])))
    assert peak < 0.9 * problem.objective_value(evaluation)
    plain = problem.build()
    solver = ca.nlpsol("plain", "ipopt", {"x": plain.z, "f": plain.cost, "g": plain.rows}, options)
    again = np.array(solver(x0=w, lbx=plain.lower, ubx=plain.upper, lbg=0, ubg=np.inf)["x"]).reshape(-1)
    polished = problem.objective_value(problem.evaluate(problem.scale(np.clip(again[: plain.n_design], 0, 1))))
    assert polished > peak * (1 - 1e-4)


def test_least_squares_multipliers_map_onto_the_nlp_rows():
    """For any multipliers ν of the solver's scaled rows (N·n_c sample rows, sample by sample, then the
    linear rows), the NLP's rows with DesignProblem.nlp_row_multipliers(ν) pull on the design with the
    same force: J_scaledᵀ ν = J_nlpᵀ ν_nlp (the coil demo: per-sample rows and rows of no sample)."""
    from springbalance.design.solvers.residuals import _LeastSquaresResiduals

    problem = _coils()
    blocks = problem.model.constraint_blocks
    assert any(block.per_sample for block in blocks) and any(not block.per_sample for block in blocks)
    residuals = _LeastSquaresResiduals(problem)
    z = np.full(problem.variables.size, 0.45)
    _, _, _, row_jacobian = residuals._full_outputs(z)
    scaled_jacobian = row_jacobian.reshape(-1, problem.variables.size)  # (N·n_c) × n
    nu = np.random.default_rng(3).random(scaled_jacobian.shape[0])
    nlp = problem.build()
    nlp_jacobian = _dense(ca.Function("j", [nlp.z], [ca.jacobian(nlp.rows, nlp.z)])(z))
    mapped = problem.nlp_row_multipliers(nu, nlp.n_rows)
    assert mapped.shape == (nlp.n_rows,) and np.all(mapped >= 0)
    assert np.allclose(nlp_jacobian.T @ mapped, scaled_jacobian.T @ nu, rtol=1e-10, atol=1e-12)


def test_a_copy_with_more_linear_rows_does_not_take_the_penalty_of_the_original():
    """The compiled residuals are shared by a problem and its copies with other linear rows (the fit to the
    arm's rounds). A penalty left on the original's residuals counts the original's linear rows (none here);
    the copy's residuals start without it, so that its normal equations see its own rows (this raised a
    shape error in the wire rounding after a clearance fit on the UR5)."""
    from springbalance.design.clearance import LinearRows

    problem = _coils()
    original = problem.least_squares_cache
    if original is None:
        from springbalance.design.solvers.residuals import _LeastSquaresResiduals

        original = problem.least_squares_cache = _LeastSquaresResiduals(problem)
    z = np.full(problem.variables.size, 0.45)
    original.set_penalty(np.ones(original.n_constraint_rows), 10.0)
    name = problem.variables.names[0]
    rows = LinearRows([name], np.array([[1.0], [-1.0]]), np.array([0.0, 5.0]), ["low", "high"])
    copy = problem.with_linear_rows(rows)
    residuals = copy.least_squares_cache
    assert residuals.problem is copy and residuals.n_constraint_rows == original.n_constraint_rows + 2
    gram, projected, squares = residuals.normal_equations(z)
    assert np.all(np.isfinite(gram)) and np.isfinite(squares)
    assert original.penalty == 10.0  # the original keeps its own penalty


def test_starts_that_ipopts_limit_left_infeasible_are_continued_before_giving_up():
    """Ten IPOPT iterations leave both coil-demo starts infeasible: without a polish the solve fails;
    with one, the starts the limit stopped continue and end feasible (IPOPT's limit counts as a budget
    stop, as least squares' does)."""
    from springbalance.design.solvers import solve_problem
    from springbalance.errors import SolverError

    problem = _coils()
    options = {"starts": 2, "seed": 0, "method": "ipopt", "max_iterations": 10, "workers": 1}
    with pytest.raises(SolverError, match="Maximum_Iterations_Exceeded"):
        solve_problem(problem, polish_iterations=0, **options)
    solution = solve_problem(problem, polish_iterations=200, **options)
    best = min((record for record in solution.starts if record.feasible), key=lambda record: record.objective)
    assert "polished after 10 iterations" in best.status
    assert problem.evaluate(solution.x).max_violation <= 1e-6


def test_scaled_row_multipliers_invert_the_nlp_mapping():
    """DesignProblem.scaled_row_multipliers spreads the NLP rows' multipliers over the solver's scaled rows
    (a row of no sample evenly over the samples) so that nlp_row_multipliers gives them back."""
    problem = _coils()
    nlp = problem.build()
    n_scaled = problem.workspace.size * len(problem.model.constraint_blocks)
    assert not all(block.per_sample for block in problem.model.constraint_blocks)  # some rows of no sample
    nu = np.random.default_rng(5).random(nlp.n_rows)
    # the constraint rows come first (those of a sample, then those of none), the objective's own rows after
    n_constraint_rows = problem.nlp_row_multipliers(np.ones(n_scaled), nlp.n_rows).nonzero()[0].size
    nu[n_constraint_rows:] = 0.0
    scaled = problem.scaled_row_multipliers(nu, 0)
    assert scaled.shape == (n_scaled,) and np.all(scaled >= 0)
    assert np.allclose(problem.nlp_row_multipliers(scaled, nlp.n_rows), nu, rtol=1e-12, atol=0)


def test_a_resolve_from_a_nearby_problems_multipliers_starts_warm():
    """The coil demo solved, then one wire held at a standard size (as wire rounding does): solved from
    the continuous design with its IPOPT multipliers, the problem with the wire held reaches the optimum
    the cold solve from the same design reaches, in less than half the iterations, and the wire stays put.
    (The static rules only: with the fatigue floor the warm start saves less, about a third.)"""
    from springbalance.design.solvers import solve_problem

    problem = _static_coils()
    solution = solve_problem(problem, starts=1, seed=0, workers=1)
    assert solution.multipliers is not None and solution.multipliers.shape == (problem.build().n_rows,)
    name = "shoulder_spring.wire_diameter"
    wire = problem.variables.names.index(name)
    held = 0.93 * solution.x[wire]  # 7 % below the optimum's wire: moves the optimum, as rounding down does
    start = solution.x.copy()
    start[wire] = held
    options = {"starts": 1, "workers": 1, "initial": start, "fixed": [name]}
    cold = solve_problem(problem, **options)
    warm = solve_problem(problem, multipliers=solution.multipliers, **options)
    assert warm.starts[0].iterations < 0.5 * cold.starts[0].iterations
    for found in (cold, warm):
        assert found.x[wire] == pytest.approx(held, rel=1e-12)
        assert problem.evaluate(found.x).max_violation <= 1e-6
    cold_value, warm_value = (problem.objective_value(problem.evaluate(found.x)) for found in (cold, warm))
    assert warm_value == pytest.approx(cold_value, rel=1e-6)
    assert warm_value > problem.objective_value(problem.evaluate(solution.x))  # the held wire costs something


def test_fixed_names_a_design_variable():
    from springbalance.design.solvers import solve_problem
    from springbalance.errors import InputError

    with pytest.raises(InputError, match="'shoulder_spring.coils' is not a design variable"):
        solve_problem(_coils(), starts=1, fixed=["shoulder_spring.coils"])


@pytest.mark.parametrize("objective", ["rms", "peak"])
def test_every_start_keeps_the_fixed_variables(objective):
    """Held variables keep their value in every start (Sobol ones too) and through every phase: a linear
    one (the stiffness, which the start's linear fit would move) and a nonlinear one (an anchor)."""
    from springbalance.design.solvers import solve_problem

    problem = _planar(objective)
    names = problem.variables.names
    held = {"shoulder.stiffness": 1234.5, "elbow.b.x": -0.1}
    start = problem.variables.start.copy()
    for name, value in held.items():
        start[names.index(name)] = value
    solution = solve_problem(problem, starts=3, seed=1, workers=1, initial=start, fixed=list(held))
    for record in solution.starts:
        for name, value in held.items():
            assert record.x[names.index(name)] == pytest.approx(value, rel=1e-9)
    free = solve_problem(problem, starts=3, seed=1, workers=1)
    value = lambda found: problem.objective_value(problem.evaluate(found.x))  # noqa: E731
    assert value(free) < value(solution)  # holding them costs something


def test_a_start_continued_with_its_multipliers_picks_up_where_ipopt_stopped():
    """A polish run continues a start from its design *and* the multipliers IPOPT stopped with: from a
    converged peak design it is done in a few iterations, where a start from the design alone (IPOPT's
    default barrier, multipliers guessed) walks the whole central path again."""
    from springbalance.design.solvers import start_points
    from springbalance.design.solvers.multistart import _MultiStartSolver

    problem = _planar("peak")
    solver = _MultiStartSolver(problem, "auto", 200, 1e-8)
    first = solver.run(0, start_points(problem, 1, 0)[0])
    assert "Solve_Succeeded" in first.status and first.multipliers is not None
    z = problem.unscale(first.x)
    continued = solver.run(0, z, False, first.multipliers)
    again = solver.run(0, z, False)
    assert continued.iterations <= 0.25 * again.iterations
    assert continued.objective == pytest.approx(first.objective, rel=1e-8)


def test_several_given_starts_come_first_with_their_own_held_values():
    """``initial`` with one row per start: those rows are the first starts (each keeps its own value of a
    held variable), the Sobol points follow and hold the first row's value."""
    from springbalance.design.solvers import solve_problem, start_points

    problem = _planar("rms")
    names = problem.variables.names
    held = names.index("shoulder.stiffness")
    given = np.repeat(np.asarray(problem.variables.start, dtype=float)[None, :], 2, axis=0)
    given[:, held] = [800.0, 1600.0]
    mask = np.zeros(problem.variables.size, dtype=bool)
    mask[held] = True
    points = start_points(problem, 5, 1, given, mask)
    assert points.shape == (5, problem.variables.size)
    np.testing.assert_allclose(problem.scale(points[:2]), given, rtol=1e-12)
    np.testing.assert_allclose(problem.scale(points[2:])[:, held], 800.0, rtol=1e-12)
    solution = solve_problem(problem, starts=3, seed=1, workers=1, initial=given, fixed=["shoulder.stiffness"])
    assert [record.x[held] for record in solution.starts] == pytest.approx([800.0, 1600.0, 800.0], rel=1e-9)


@pytest.mark.parametrize(
    "rows, columns", [(None, 3), (1, 7), (0, 0), (3, 0)], ids=["short", "narrow", "no-rows", "more-rows-than-starts"]
)
def test_initial_of_the_wrong_shape_is_refused(rows, columns):
    from springbalance.design.solvers import solve_problem
    from springbalance.errors import InputError

    problem = _planar("rms")
    n = problem.variables.size
    bad = np.zeros(columns or n) if rows is None else np.zeros((rows, columns or n))
    with pytest.raises(InputError, match=rf"initial must hold {n} design variables.*starts=2.*shape"):
        solve_problem(problem, starts=2, initial=bad)
