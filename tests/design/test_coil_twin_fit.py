"""The coils' continuation from their ideal twin fitted to the arm (springbalance.design.coil_start): the
twin is fitted at the coils' envelope radius, the coils start from its fitted design and from its distinct
optima, inside the rows of its fit, and the coil design that follows keeps the clearance.

The arm is urdf/two_link_planar_collision.urdf (link1: box 0.5 × 0.04 × 0.04 m along x of its frame; link2:
box 0.4 × 0.03 × 0.03 m; both joints about (0, −1, 0)) over its whole range (shoulder ±90°, elbow ±150°),
with every anchor in the arm's plane (32 Sobol poses). A music-wire extension coil s1 (outer diameter at most 30 mm) from above
the shoulder to link1 carries the arm's weight, and an ideal zero-free-length spring s2 couples link1 to
link2. With the elbow folded back, link2 lies across the line from above the shoulder to link1, so the ideal
optimum (tests/design/test_clearance_constraint.py shows it for two zero-free-length springs) passes through
link2; only the fit to the arm moves s1 clear of it. Every check below measures the URDF's own shapes
(springbalance.results.clearance), not the rows the fit linearises.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.design import coil_start
from springbalance.design.solvers import FEASIBILITY_TOLERANCE, solve_problem
from springbalance.io.config import config_from_dict
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring

ROOT = Path(__file__).resolve().parents[2]
OUTER = 0.03  # [m] the coil's envelope: its capsule is at most OUTER / 2 in radius
MARGIN = 0.005  # [m]
CHECK = 64  # poses the fit checks
RECORD = {
    "mechanism": {"urdf": str(ROOT / "urdf" / "two_link_planar_collision.urdf")},
    "workspace": {"kind": "sobol", "n": 32, "seed": 0},
    "springs": [
        {
            "name": "s1",
            "type": "extension",
            "material": "music_wire",
            "max_outer_diameter": OUTER,
            "a": {"body": "universe", "box": {"lower": [-0.1, 0, 0.2], "upper": [0.1, 0, 0.4]}},
            "b": {"body": "link1", "box": {"lower": [0.3, 0, -0.05], "upper": [0.5, 0, 0.05]}},
        },
        {
            "name": "s2",
            "type": "zero_free_length",
            "stiffness": {"lower": 0, "upper": 5000},
            "a": {"body": "link1", "box": {"lower": [-0.1, 0, -0.1], "upper": [0.45, 0, 0.1]}},
            "b": {"body": "link2", "box": {"lower": [0.02, 0, -0.05], "upper": [0.4, 0, 0.05]}},
        },
    ],
    "clearance": {"margin": MARGIN, "check_samples": CHECK},
    "solve": {"starts": 3, "seed": 0},
}
OPTIONS = {"starts": 3, "seed": 0, "method": "auto", "max_iterations": 100, "tolerance": 1e-8}


@pytest.fixture(scope="module")
def config():
    return config_from_dict(RECORD, ROOT, "coil twin fit")


@pytest.fixture(scope="module")
def found(config):
    start = coil_start.coil_starts(config.problem, 3, **OPTIONS)
    assert start is not None
    return start


def _twin_at(found, names: list[str], x: np.ndarray) -> np.ndarray:
    """The twin's design with the values of the coil problem's design ``x`` (variables ``names``) for every
    variable the two share (the anchors, s2's stiffness); s1's ideal law from the twin's optimum (a law does not
    move a capsule)."""
    values = dict(zip(found.twin.variables.names, found.twin_x))
    values.update({name: value for name, value in zip(names, x) if name in values})
    return np.array([values[name] for name in found.twin.variables.names])


def _closest(problem: sb.DesignProblem, x: np.ndarray, samples: int, radius: float | None = None) -> dict:
    """Per spring, its smallest distance [m] to the arm's URDF shapes over ``samples`` Sobol poses; an ideal
    spring is a capsule of ``radius`` [m], a coil one of half its outer diameter."""
    report = sb.DesignResult(problem, x).clearance(samples=samples, radius=radius, margin=MARGIN)
    return {row.spring: row.distance for row in report.rows}


def _anchors(names: list[str]) -> list[int]:
    """The indices of the anchor coordinates among ``names`` (``<spring>.a.x`` …)."""
    return [i for i, name in enumerate(names) if name.split(".")[1] in ("a", "b")]


def test_the_unfitted_twin_passes_through_link2_at_the_envelope_radius(found):
    """The case is one the continuation is for: the twin's optimum overlaps the arm, so its fit has rows."""
    assert _closest(found.twin, found.twin_x, 4 * CHECK, OUTER / 2)["s1"] < MARGIN
    assert found.rows is not None and len(found.rows) > 0


def test_the_coils_also_keep_the_side_of_each_link_the_fitted_twin_passes_on(config, found):
    """Besides the fit's rows (none when the design kept was clear as it stood), two rows per spring and object
    (the plane at the pair's closest pose): the coils' first start (the twin's kept design, wound) meets them."""
    sides = [label for label in found.rows.labels if label.endswith("the side it passes on")]
    assert sides and any(label.startswith("s1 clear of link2") for label in sides)
    kept = config.problem.with_linear_rows(found.rows)
    assert kept.linear_violation(found.starts[0]) <= FEASIBILITY_TOLERANCE


def test_the_fitted_twin_keeps_the_margin_and_the_coils_start_inside_its_rows(config, found):
    problem, names = config.problem, config.problem.variables.names
    fitted = found.starts[0]
    # the twin at the first start's anchors, capsules as wide as the envelope: clear of the arm by the margin
    # at the fit's poses and at its 4x denser final check (the rows hold only as linearised; these are the
    # URDF's shapes)
    distances = _closest(found.twin, _twin_at(found, names, fitted), 4 * CHECK, OUTER / 2)
    assert min(distances.values()) >= MARGIN - 1e-4, distances
    # the kept rows are over variables the coils share with the twin (anchors only: a wire or coil diameter is
    # not the twin's), and every start from the fitted design meets them
    rows = found.rows
    used = {rows.names[i] for i in np.flatnonzero(np.any(rows.matrix != 0, axis=0))}
    assert used and used <= set(names) and {name.split(".")[1] for name in used} <= {"a", "b"}, used
    kept = problem.with_linear_rows(found.rows)
    assert kept.linear_violation(fitted) <= FEASIBILITY_TOLERANCE
    # the coil wound at the fitted design is no wider than the envelope the twin was fitted with
    index = {name: i for i, name in enumerate(names)}
    assert fitted[index["s1.mean_diameter"]] + fitted[index["s1.wire_diameter"]] <= OUTER + 1e-12


def test_the_other_starts_are_the_twins_distinct_optima_wound_into_coils(config, found):
    names = config.problem.variables.names
    index = {name: i for i, name in enumerate(names)}
    twin_index = {name: i for i, name in enumerate(found.twin.variables.names)}
    starts = found.starts
    assert starts.shape[0] >= 2 and starts.shape[1] == len(names)
    for i in range(starts.shape[0]):
        for j in range(i):
            assert not np.allclose(starts[i], starts[j])
    # after the fitted design comes the twin's best optimum: its anchors, and a coil of its rate
    # k = G d⁴ / (8 D³ n) (Shigley eq. 10-9)
    optimum = starts[1]
    for name in (names[i] for i in _anchors(names)):
        assert optimum[index[name]] == pytest.approx(found.twin_x[twin_index[name]], abs=1e-12)
    coil = config.problem.springs[0]
    assert isinstance(coil, HelicalExtensionSpring)
    d, D, n = (optimum[index[f"s1.{key}"]] for key in ("wire_diameter", "mean_diameter", "active_coils"))
    rate = coil.material.shear_modulus * d**4 / (8 * D**3 * n)  # [N/m]
    assert rate == pytest.approx(found.twin_x[twin_index["s1.stiffness"]], rel=1e-9)
    # the twin's best optimum is its unfitted one: it overlaps where the fitted start keeps clear
    assert not np.allclose(starts[0][_anchors(names)], optimum[_anchors(names)])


def test_the_coils_solved_from_those_starts_inside_its_rows_clear_the_arm(config, found):
    """The multi-start of the coils alone (no fit after it): from the starts and inside the kept rows, the coil
    clears the arm's shapes at 10x the poses the fit checked (the rows are linearised, so the last millimetres
    of the margin are the fit's job); from the same starts without the rows it passes through link2."""
    bare = config.problem.with_linear_rows(None)
    inside = solve_problem(config.problem.with_linear_rows(found.rows), initial=found.starts, **OPTIONS)
    assert min(_closest(bare, inside.x, 10 * CHECK).values()) > 0
    outside = solve_problem(bare, initial=found.starts, **OPTIONS)
    assert _closest(bare, outside.x, 10 * CHECK)["s1"] < 0


def test_the_coil_design_keeps_the_margin(config):
    """The whole solve (twin, its fit, the coils from its starts, their own fit, the check at unseen poses)."""
    result = sb.solve(config)
    assert result.fit is not None and result.fit.converged
    # the coils themselves (capsules of half their own outer diameter) at 10x the poses the fit checked
    distances = _closest(result.problem.with_linear_rows(None), result.x, 10 * CHECK)
    assert min(distances.values()) >= MARGIN - 1e-4, distances
    assert "overlap" not in {flag.kind for flag in result.failures()}
