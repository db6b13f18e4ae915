"""IPOPT's stop on a plateau of the objective (design/plateau.py): it stops a solve whose objective no longer falls,
never one whose objective falls or whose iterate breaks a row, and only the NLPs of helical coils use it."""

import casadi as ca
import numpy as np
import pytest

import springbalance as sb
from springbalance.design import plateau
from springbalance.design.clearance import LinearRows
from springbalance.design.plateau import MIN_ITERATIONS, PLATEAU_STATUS, RELATIVE_GAIN, WINDOW, Plateau
from springbalance.design.structured_nlp import StructuredNlp
from springbalance.io.config import load_config
from springbalance.results.failure_flags import last_solver_status

IPOPT = {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes", "ipopt.tol": 1e-14, "ipopt.max_iter": 400}


def _iterate(callback, objective, row):
    """One iteration's call of the callback (as IPOPT's interface makes it): its answer, 1 to stop."""
    values = {"x": np.zeros(callback.n_x), "f": objective, "g": np.full(callback.n_g, row)}
    return int(callback.call(values)["stop"])


def _creeping():
    """min 1 + r^1.1 (r = |x|) over x₀ ≥ -5: IPOPT's steps shrink while its gradient (1.1 r^0.1) stays far above a
    tolerance of 1e-14, so it iterates long after the objective is 1 to many digits."""
    x = ca.MX.sym("x", 2)
    return {"x": x, "f": 1 + (x[0] ** 2 + x[1] ** 2 + 1e-30) ** 0.55, "g": x[0] + 5}


def test_ipopt_stops_on_a_plateau_at_the_objective_it_creeps_to():
    nlp = _creeping()
    alone = ca.nlpsol("alone", "ipopt", nlp, IPOPT)
    reference = float(alone(x0=[1, 2], lbg=0, ubg=np.inf)["f"])
    assert alone.stats()["iter_count"] > MIN_ITERATIONS + 50
    callback = Plateau(2, 1)
    stopped = ca.nlpsol("stopped", "ipopt", nlp, {**IPOPT, "iteration_callback": callback})
    objective = float(stopped(x0=[1, 2], lbg=0, ubg=np.inf)["f"])
    assert stopped.stats()["return_status"] == "User_Requested_Stop" and callback.stopped
    assert stopped.stats()["iter_count"] <= MIN_ITERATIONS + WINDOW
    assert abs(objective - reference) <= RELATIVE_GAIN * reference


def test_it_goes_on_while_the_objective_falls_and_stops_once_the_fall_is_below_its_fraction():
    callback = Plateau(3, 2)
    falling = [1.001 ** (-k) for k in range(200)]  # 3 % over a window: far above the fraction
    assert not any(_iterate(callback, value, 0.0) for value in falling)
    flat = falling[-1]
    answers = [_iterate(callback, flat, 0.0) for _ in range(WINDOW)]
    # over 30 iterations 0.1 % each falls 3 %: only a window that starts on the flat part (at the last falling value,
    # equal to it) is a plateau, the first one ends WINDOW - 1 iterations into the flat part
    assert answers.index(1) == WINDOW - 1 and callback.stopped


def test_it_never_stops_an_iterate_that_breaks_a_row_nor_before_its_first_iterations():
    broken = Plateau(1, 4)
    assert not any(_iterate(broken, 1.0, -1e-3) for _ in range(3 * MIN_ITERATIONS))
    early = Plateau(1, 4)
    answers = [_iterate(early, 1.0, 0.0) for _ in range(MIN_ITERATIONS + 1)]
    assert answers.index(1) == MIN_ITERATIONS  # (no earlier: the objective was flat from the start)
    after_break = Plateau(1, 1)  # the window's first iterate broke a row: no plateau measured from it
    answers = [
        _iterate(after_break, 1.0, -1.0 if k == MIN_ITERATIONS - WINDOW else 0.0) for k in range(MIN_ITERATIONS + 2)
    ]
    assert answers.index(1) == MIN_ITERATIONS + 1


def test_only_coils_stop_on_a_plateau():
    coils = load_config("examples/two_link.yaml").problem
    assert plateau.stops_on_plateau(coils)
    mechanism = sb.Mechanism.from_urdf("urdf/two_link_planar.urdf")
    spring = sb.ExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.1, 0, 0.05], [0.1, 0, 0.3])),
        sb.Anchor("link1", sb.Free([0.05, 0, 0], [0.5, 0, 0])),
        "shoulder",
        stiffness=sb.Free(0, 3000),
        free_length=sb.Free(0.02, 0.3),
    )
    ideal = sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, 32, seed=2), [spring])
    assert not plateau.stops_on_plateau(ideal)
    names = list(ideal.variables.names)  # nor a fitting round of ideal springs
    rows = LinearRows(names[:1], np.ones((1, 1)), np.zeros(1), [f"{names[0]} ≥ 0"])
    assert not plateau.stops_on_plateau(ideal.with_linear_rows(rows))


def test_a_structured_solve_stopped_on_a_plateau_reports_it_as_finished(monkeypatch):
    """The demo's coils with a plateau that any two feasible iterates make: the solve ends on it, and its status is
    a finished one (neither a failure nor the iteration limit)."""
    monkeypatch.setattr(plateau, "MIN_ITERATIONS", 3)
    monkeypatch.setattr(plateau, "WINDOW", 1)
    monkeypatch.setattr(plateau, "RELATIVE_GAIN", 1e6)
    problem = load_config("examples/two_link.yaml").problem
    structured = StructuredNlp(problem)
    nlp = structured.nlp
    start = np.clip(problem.unscale(problem.variables.start), 0.0, 1.0)
    options = {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes", "ipopt.tol": 1e-8}
    _, status, iterations, _ = structured.solve(start, nlp.lower, nlp.upper, options, 300)
    assert status == PLATEAU_STATUS
    assert iterations < 300
    assert last_solver_status(f"ipopt: {status}") == (PLATEAU_STATUS, False)


@pytest.mark.parametrize("status", ["Maximum_Iterations_Exceeded", "User_Requested_Stop"])
def test_other_statuses_keep_their_meaning(status):
    assert last_solver_status(f"ipopt: {status}") == (status, status == "User_Requested_Stop")


def test_a_plateau_where_rows_outside_the_solve_are_broken_stops_nothing():
    """A working set's plateau on a design that breaks rows the solve does not see: the callback asks once, then lets
    IPOPT go on as without it (its own tolerance or limit; the working set then grows)."""
    asked = []

    def broken(x):
        asked.append(x.size)
        return False

    callback = Plateau(2, 1, broken)
    assert not any(_iterate(callback, 1.0, 0.0) for _ in range(3 * MIN_ITERATIONS))
    assert callback.gave_up and not callback.stopped and asked == [2]
    met = Plateau(2, 1, lambda x: True)
    assert [_iterate(met, 1.0, 0.0) for _ in range(MIN_ITERATIONS + 1)].index(1) == MIN_ITERATIONS
