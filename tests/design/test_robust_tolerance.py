"""The robust design over the springs' tolerance box (docs/model.md §3.10), against brute force: every one of
the 8² = 64 corner builds of a two-spring design evaluated by the library as a design of its own (its laws
changed by hand: k(1 ± ρ), F0 ± f, l0 ± λ − t), and the adjusters' best settings per build from a bounded
linear least squares (the residual is affine in the settings; columns by finite differences)."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import lsq_linear

import springbalance as sb
from springbalance.design.tolerance import analyse_tolerance
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.errors import InputError
from springbalance.io.config import config_from_dict
from springbalance.results.report import result_table
from springbalance.springs.tolerance_grades import grade_box

URDF = Path(__file__).resolve().parents[2] / "urdf"
BOX = {"grade": None, "rate": 0.1, "initial_tension": 3.0, "free_length": 0.004}
RHO, F, LAM = 0.1, 3.0, 0.004
TRAVEL = 0.006  # [m]
ALL_CORNERS = list(itertools.product(itertools.product((-1.0, 1.0), repeat=3), repeat=2))  # ((a, b, c), (a, b, c))


@pytest.fixture(scope="module")
def arm():
    mechanism = sb.Mechanism.from_urdf(URDF / "two_link_planar.urdf")
    joints = np.random.default_rng(3).uniform(-1.2, 1.2, size=(24, 2))
    return mechanism, sb.Workspace.from_array(mechanism, joints)


def _law_spring(kind, name, a, b, law):
    """An ideal spring of ``kind`` with the fixed law ``(k, l0, T)`` between anchor points a and b."""
    k, l0, tension = law
    ends = sb.Anchor(a[0], tuple(a[1])), sb.Anchor(b[0], tuple(b[1]))
    if kind == "extension":
        return sb.ExtensionSpring(*ends, name, stiffness=k, free_length=l0, initial_tension=tension, keep_tension=False)
    return sb.CompressionSpring(*ends, name, stiffness=k, free_length=l0, preload=tension)


def _free_springs():
    box = sb.Free
    return [
        sb.ExtensionSpring(
            sb.Anchor("universe", box((-0.05, 0, 0.05), (0.05, 0, 0.3))), sb.Anchor("link1", box((0.05, 0, 0), (0.5, 0, 0))),
            "shoulder", stiffness=box(100, 3000), free_length=box(0.02, 0.2), initial_tension=box(5, 50), keep_tension=False,
        ),
        sb.ExtensionSpring(
            sb.Anchor("universe", box((-0.3, 0, -0.1), (0.3, 0, 0.6))), sb.Anchor("link2", box((0.02, 0, 0), (0.4, 0, 0))),
            "forearm", stiffness=box(50, 2000), free_length=box(0.02, 0.2), initial_tension=box(5, 50), keep_tension=False,
        ),
    ]  # fmt: skip


def _fixed(problem, x):
    """Per spring of a solved problem: (kind, name, end a, end b, nominal law (k, l0, T))."""
    nominal, base = problem.scenario_problem(0), problem.model.scenario_vector(x, 0)
    out = []
    for spring in nominal.springs:
        values = nominal.model.spring_values(spring, base)
        ends = [(spring.anchors[e].body, nominal.model.anchor_point(spring, e, base)) for e in ("a", "b")]
        law = (values["stiffness"], values["free_length"], values.get("initial_tension", values.get("preload", 0.0)))
        out.append((spring.kind, spring.name, *ends, law))
    return out


def _corner_law(law, signs, shift=0.0):
    (k, l0, tension), (a, b, c) = law, signs
    return k * (1 + a * RHO), l0 + c * LAM - shift, tension + b * F


def _build_tau(arm, fixed, corner, shifts=(0.0, 0.0)):
    mechanism, workspace = arm
    springs = [
        _law_spring(kind, name, a, b, _corner_law(law, signs, t))
        for (kind, name, a, b, law), signs, t in zip(fixed, corner, shifts)
    ]
    problem = sb.DesignProblem(mechanism, workspace, springs)
    return problem.evaluate(np.zeros(0)).tau


def _rms(tau):
    return float(np.sqrt(np.mean(tau**2)))


def _brute_worst(arm, fixed, adjust=False):
    """The worst RMS over the 64 builds (each re-balanced within the travel when ``adjust``)."""
    worst = 0.0
    step = 1e-6
    for corner in ALL_CORNERS:
        tau = _build_tau(arm, fixed, corner)
        if adjust:
            columns = [
                ((_build_tau(arm, fixed, corner, shifts) - tau) / step).reshape(-1)
                for shifts in ((step, 0.0), (0.0, step))
            ]
            best = lsq_linear(np.stack(columns, axis=1), -tau.reshape(-1), bounds=(-TRAVEL, TRAVEL))
            tau = tau + (np.stack(columns, axis=1) @ best.x).reshape(tau.shape)
        worst = max(worst, _rms(tau))
    return worst


def _mixed_problem(arm, corners="exact", travel=None):
    """An extension spring and a compression spring with fixed laws, robust over their box."""
    mechanism, workspace = arm
    springs = [
        _law_spring("extension", "up", ("universe", (0.0, 0, 0.25)), ("link1", (0.3, 0, 0)), (900.0, 0.12, 10.0)),
        _law_spring("compression", "push", ("link1", (0.1, 0, -0.05)), ("link2", (-0.1, 0, 0)), (400.0, 0.4, 5.0)),
    ]
    spec = ToleranceSpec(**BOX, robust=True, corners=corners, adjuster_travel=travel)
    return sb.DesignProblem(mechanism, workspace, springs, tolerance=spec)


def test_each_case_is_its_corners_law(arm):
    problem = _mixed_problem(arm, travel=TRAVEL)
    x = np.random.default_rng(0).uniform(-TRAVEL, TRAVEL, problem.variables.size)  # the adjusters' settings
    fixed = _fixed(problem, x)
    blocks = problem.evaluate(x).tau.reshape(len(problem.scenarios), -1, 2)
    assert len(problem.scenarios) == 1 + 16
    for s, case in enumerate(problem.corners.cases):
        if not case.strengths:
            np.testing.assert_allclose(blocks[s], _build_tau(arm, fixed, ((0, 0, 0), (0, 0, 0))), atol=1e-10)
            continue
        signs, shifts = [], []
        for kind, name, *_ in fixed:
            r, p = case.strengths[name]  # + a stiffer / stronger spring: more force magnitude
            signs.append((r, p, -p if kind == "extension" else p))
            shifts.append(x[problem.corners.adjusters[(name, s)]])
        np.testing.assert_allclose(blocks[s], _build_tau(arm, fixed, signs, shifts), atol=1e-10)


def test_a_grades_box_follows_the_coil(arm):
    mechanism, workspace = arm
    values = {"wire_diameter": 0.003, "mean_diameter": 0.024, "active_coils": 40.0, "initial_tension": 20.0}
    coil = sb.HelicalExtensionSpring(
        sb.Anchor("universe", (0, 0, 0.25)), sb.Anchor("link1", (0.3, 0, 0)), "c", **values
    )
    problem = sb.DesignProblem(mechanism, workspace, [coil], tolerance=ToleranceSpec(robust=True))  # grade 2
    law = problem.springs[0].derived_values(values)
    box = grade_box("extension", 0.003, 0.024, 40.0, law["free_length"], law["stiffness"], 20.0, 2)
    blocks = problem.evaluate(np.zeros(0)).tau.reshape(len(problem.scenarios), -1, 2)
    for s, case in enumerate(problem.corners.cases[1:], start=1):
        r, p = case.strengths["c"]
        ideal = sb.ExtensionSpring(
            coil.a, coil.b, "c", stiffness=law["stiffness"] * (1 + r * box.rate),
            free_length=law["free_length"], initial_tension=20.0 + p * box.initial_tension, keep_tension=False,
        )  # fmt: skip
        plain = sb.DesignProblem(mechanism, workspace, [ideal]).evaluate(np.zeros(0)).tau
        mass = coil.spring_mass(values) * 0  # the coil's own mass is in both: compare the law's share only
        nominal = sb.DesignProblem(
            mechanism, workspace, [sb.ExtensionSpring(coil.a, coil.b, "c", stiffness=law["stiffness"],
            free_length=law["free_length"], initial_tension=20.0, keep_tension=False)],
        ).evaluate(np.zeros(0)).tau  # fmt: skip
        np.testing.assert_allclose(blocks[s] - blocks[0], plain - nominal + mass, atol=1e-9)
    assert box.initial_tension > 0.3  # grade 2's ± on a 20 N initial tension is not negligible


def test_four_corners_per_spring_are_the_worst_of_all_sixty_four(arm):
    problem = _mixed_problem(arm)
    fixed = _fixed(problem, np.zeros(0))
    brute = np.stack([_build_tau(arm, fixed, corner) for corner in ALL_CORNERS])  # 64×N×nv
    cases = problem.evaluate(np.zeros(0)).tau.reshape(len(problem.scenarios), -1, 2)[1:]  # the 16 corners
    assert max(_rms(t) for t in cases) == pytest.approx(max(_rms(t) for t in brute), rel=1e-12)
    assert np.abs(cases).max() == pytest.approx(np.abs(brute).max(), rel=1e-12)
    joint_peaks = [np.abs(t).max(axis=0).sum() for t in brute]
    assert max(np.abs(t).max(axis=0).sum() for t in cases) == pytest.approx(max(joint_peaks), rel=1e-12)
    # the peak needs only the strong/weak combinations (both springs keep their sense over these poses)
    pairs = _mixed_problem(arm, "strong_weak").evaluate(np.zeros(0)).tau.reshape(5, -1, 2)[1:]
    assert np.abs(pairs).max() == pytest.approx(np.abs(brute).max(), rel=1e-12)
    # every spring strong / every spring weak: two of the builds, so a lower bound
    uniform = _mixed_problem(arm, "uniform").evaluate(np.zeros(0)).tau.reshape(3, -1, 2)[1:]
    assert max(_rms(t) for t in uniform) <= max(_rms(t) for t in brute) * (1 + 1e-12)


@pytest.fixture(scope="module")
def designs(arm):
    mechanism, workspace = arm
    out = {}
    for label, spec in (
        ("plain", None),
        ("nominal", ToleranceSpec(**BOX)),
        ("robust", ToleranceSpec(**BOX, robust=True)),
        ("adjusted", ToleranceSpec(**BOX, robust=True, adjuster_travel=TRAVEL)),
        ("uniform", ToleranceSpec(**BOX, robust=True, corners="uniform")),
    ):
        problem = sb.DesignProblem(mechanism, workspace, _free_springs(), tolerance=spec)
        out[label] = sb.solve(problem, starts=1, progress=False, verify="off", workers=1)
    return out


def test_robust_design_lowers_the_worst_build(arm, designs):
    plain, nominal, robust = designs["plain"], designs["nominal"], designs["robust"]
    # a tolerance that is not robust changes nothing of the design
    np.testing.assert_array_equal(nominal.x, plain.x)
    worst_nominal = _brute_worst(arm, _fixed(nominal.problem, nominal.x))
    worst_robust = _brute_worst(arm, _fixed(robust.problem, robust.x))
    assert worst_robust < worst_nominal
    # the robust objective is the worst build's RMS: the 16 corners reach the worst of all 64
    assert robust.problem.objective_value(robust.evaluation) == pytest.approx(worst_robust, rel=1e-9)
    # and the nominal law of the robust design is worse than the nominal design's: the price of robustness
    assert _rms(robust.problem.scenario_problem(0).evaluate(robust.problem.model.scenario_vector(robust.x, 0)).tau) > (
        _rms(nominal.evaluation.tau)
    )


def test_two_uniform_corners_miss_the_worst_build(arm, designs):
    # designed for every spring strong and every spring weak only, the mixed builds are far worse than the two
    # it saw, and worse than the exact robust design's worst build
    uniform, robust = designs["uniform"], designs["robust"]
    worst = _brute_worst(arm, _fixed(uniform.problem, uniform.x))
    assert worst > 1.5 * uniform.problem.objective_value(uniform.evaluation)
    assert worst > _brute_worst(arm, _fixed(robust.problem, robust.x))


def test_adjusters_rebalance_each_corner_within_the_travel(arm, designs):
    robust, adjusted = designs["robust"], designs["adjusted"]
    corners = adjusted.problem.corners
    settings = np.array([adjusted.x[i] for i in corners.adjusters.values()])
    assert np.all(np.abs(settings) <= TRAVEL + 1e-12) and np.abs(settings).max() > 1e-3
    worst_adjusted = _brute_worst(arm, _fixed(adjusted.problem, adjusted.x), adjust=True)
    assert worst_adjusted <= _brute_worst(arm, _fixed(robust.problem, robust.x)) + 1e-9
    # the design's own settings are feasible ones, so its worst case is no better than the best settings'
    assert adjusted.problem.objective_value(adjusted.evaluation) >= worst_adjusted - 1e-9
    table = analyse_tolerance(adjusted).corners
    assert [row["name"] for row in table] == adjusted.problem.corners.names
    assert table[0]["adjusters"] == {"shoulder": 0.0, "forearm": 0.0}  # the nominal build needs no setting


def test_robust_design_round_trips_through_design_json(designs, tmp_path):
    adjusted = designs["adjusted"]
    path = adjusted.save(tmp_path / "design.json")
    loaded = sb.DesignResult.load(path)
    assert loaded.problem.tolerance == adjusted.problem.tolerance
    assert loaded.problem.variables.names == adjusted.problem.variables.names
    assert loaded.problem.objective_value(loaded.evaluation) == adjusted.problem.objective_value(adjusted.evaluation)
    text = result_table(loaded)
    assert "robust design over 16 corners (exact" in text and "re-balanced by its adjusters within ±6.00 mm" in text


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"objective": "peak_then_joints"}, "objective 'peak_then_joints' is not supported"),
        ({"scenarios": [sb.Scenario("heavy")]}, "cannot also have scenarios"),
    ],
)
def test_unsupported_combinations_are_named(arm, options, message):
    mechanism, workspace = arm
    with pytest.raises(InputError, match=message):
        sb.DesignProblem(mechanism, workspace, _free_springs(), tolerance=ToleranceSpec(**BOX, robust=True), **options)


def test_ideal_springs_under_a_grade_have_no_box(arm):
    mechanism, workspace = arm
    with pytest.raises(InputError, match="no spring has a tolerance box"):
        sb.DesignProblem(mechanism, workspace, _free_springs(), tolerance=ToleranceSpec(robust=True))


@pytest.mark.parametrize(
    ("record", "message"),
    [
        (
            {"rate": 0.1, "robust": True, "corners": "all"},
            "tolerance.corners must be one of exact, strong_weak, uniform",
        ),
        ({"rate": 0.1, "corners": "uniform"}, "tolerance.corners: 'uniform' needs robust: true"),
        ({"rate": 0.1, "robust": "yes"}, "tolerance.robust must be true or false, got 'yes'"),
    ],
)
def test_bad_robust_records(record, message):
    with pytest.raises(InputError, match=message):
        ToleranceSpec.from_record(record)


def test_a_config_designs_for_the_box_and_refuses_stock_parts():
    record = {
        "mechanism": {"urdf": str(URDF / "two_link_planar.urdf")},
        "workspace": {"kind": "grid", "n": 4, "ranges": {"shoulder": [-1, 1], "elbow": [-1, 1]}},
        "springs": [
            {
                "name": "s1", "type": "extension", "ideal": True, "stiffness": {"lower": 100, "upper": 900},
                "free_length": 0.1, "initial_tension": 5.0, "keep_tension": False,
                "a": {"body": "universe", "point": [0, 0, 0.2]}, "b": {"body": "link1", "point": [0.3, 0, 0]},
            }
        ],
        "tolerance": {"rate": 0.1, "robust": True, "corners": "strong_weak", "adjuster_travel": 0.01},
    }  # fmt: skip
    config = config_from_dict(record)
    assert config.problem.corners.names == ["nominal", "k+F+", "k-F-"]
    assert config.problem.variables.names == ["s1.stiffness", "s1.adjuster[k+F+]", "s1.adjuster[k-F-]"]
    with pytest.raises(InputError, match="stock parts cannot be chosen for a robust design"):
        sb.solve(config, stock=[])
    with pytest.raises(InputError, match="tolerance must be a springbalance ToleranceSpec or None, got dict"):
        sb.DesignProblem(config.mechanism, config.workspace, config.springs, tolerance={"robust": True})
