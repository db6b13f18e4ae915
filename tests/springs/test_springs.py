"""Spring laws of docs/model.md §3 beyond extension springs: compression/gas, constant force,
torsional, their mixing, records and reports.

The physics tests compare the library's residual torque with the finite-difference gradient
of an independently computed total potential (``physics_helpers.ReferencePotential``:
Pinocchio's gravity potential, anchor positions from ``framesForwardKinematics``, the laws of
docs/model.md §3 written out, torsional springs on the joint coordinate).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from physics_helpers import ReferencePotential, RefSpring, RefTorsional

URDF = Path(__file__).resolve().parents[2] / "urdf"
RELATIVE = 1e-6


@pytest.fixture(scope="module")
def ur5():
    return sb.Mechanism.from_robot("ur5")


def _assert_gradient(mechanism, workspace, evaluation, reference):
    for i, q in enumerate(workspace.configurations):
        expected = reference.torque(q)
        scale = max(np.max(np.abs(expected)), 1.0)
        np.testing.assert_allclose(evaluation.tau[i], expected, rtol=0, atol=RELATIVE * scale, err_msg=f"sample {i}")
        v = reference(q)
        assert abs(evaluation.potential[i] - v) <= 1e-10 * max(abs(v), 1.0), (i, evaluation.potential[i], v)


@pytest.mark.parametrize("seed", [0, 1])
def test_mixed_springs_on_ur5_match_potential_gradient(ur5, seed):
    """Every law of docs/model.md §3 in one design, plus a torsional spring (tau = dV/dq, §4)."""
    rng = np.random.default_rng(seed)
    workspace = sb.Workspace.from_array(ur5, rng.uniform(-np.pi, np.pi, size=(12, ur5.nv)), ordered=False)
    pa, pb = rng.uniform(-0.2, 0.2, size=(4, 2, 3)).transpose(1, 0, 2)
    ground = rng.uniform([-0.4, -0.4, 0.0], [0.4, 0.4, 0.8], size=(4, 3))
    k, l0, f0 = rng.uniform(100, 3000, 4), rng.uniform(0.3, 1.5, 4), rng.uniform(5, 80, 4)
    springs = [
        sb.ExtensionSpring(
            sb.Anchor("universe", ground[0]),
            sb.Anchor("upper_arm_link", pb[0]),
            stiffness=k[0],
            free_length=l0[0],
            initial_tension=f0[0],
            keep_tension=False,
        ),
        sb.CompressionSpring(
            sb.Anchor("universe", ground[1]),
            sb.Anchor("forearm_link", pb[1]),
            stiffness=k[1],
            free_length=l0[1],
            preload=f0[1],
            stays_compressed=False,
        ),
        sb.GasSpring(
            sb.Anchor("shoulder_link", pa[2]),
            sb.Anchor("forearm_link", pb[2]),
            stiffness=k[2],
            free_length=l0[2],
            preload=f0[2],
            stays_compressed=False,
        ),
        sb.ConstantForceSpring(sb.Anchor("upper_arm_link", pa[3]), sb.Anchor("wrist_1_link", pb[3]), force=-f0[3]),
        sb.TorsionalSpring("elbow_joint", stiffness=12.0, neutral_angle=0.4, preload=-3.0),
        sb.TorsionalSpring("shoulder_lift_joint", stiffness=40.0, neutral_angle=-1.2),
    ]
    reference = ReferencePotential(
        ur5.model,
        [
            RefSpring("universe", tuple(ground[0]), "upper_arm_link", tuple(pb[0]), k[0], l0[0], f0[0]),
            RefSpring(
                "universe", tuple(ground[1]), "forearm_link", tuple(pb[1]), k[1], l0[1], f0[1], law="compression"
            ),
            RefSpring(
                "shoulder_link", tuple(pa[2]), "forearm_link", tuple(pb[2]), k[2], l0[2], f0[2], law="compression"
            ),
            RefSpring(
                "upper_arm_link", tuple(pa[3]), "wrist_1_link", tuple(pb[3]), 0.0, 0.0, -f0[3], law="constant_force"
            ),
        ],
        [RefTorsional("elbow_joint", 12.0, 0.4, -3.0), RefTorsional("shoulder_lift_joint", 40.0, -1.2)],
    )
    problem = sb.DesignProblem(ur5, workspace, springs)
    evaluation = problem.evaluate(np.zeros(0))
    _assert_gradient(ur5, workspace, evaluation, reference)
    # States and generalised forces: lengths and tensions (pushing springs: negative),
    # joint angles and spring torques.
    lengths = np.array([reference.lengths(q) for q in workspace.configurations])
    np.testing.assert_allclose(evaluation.lengths[:, :4], lengths, rtol=1e-12)
    np.testing.assert_allclose(evaluation.tensions[:, 1], -(f0[1] + k[1] * (l0[1] - lengths[:, 1])), rtol=1e-12)
    np.testing.assert_allclose(evaluation.tensions[:, 3], -f0[3], rtol=1e-12)
    elbow = workspace.joint_values[:, 2]
    np.testing.assert_allclose(evaluation.lengths[:, 4], elbow, rtol=0, atol=0)
    np.testing.assert_allclose(evaluation.tensions[:, 4], 12.0 * (elbow - 0.4) - 3.0, rtol=1e-12)


def test_torsional_spring_on_continuous_joint():
    """A continuous joint stores (cos, sin); the spring acts on the angle."""
    urdf = (URDF / "single_link_r2.urdf").read_text().replace('type="revolute"', 'type="continuous"')
    mechanism = sb.Mechanism.from_urdf_string(urdf, gravity=9.8)
    assert mechanism.joints[0].kind == "continuous"
    workspace = sb.Workspace.grid(mechanism, 13, ranges={"theta": (-2.5, 2.5)})
    spring = sb.TorsionalSpring("theta", stiffness=3.0, neutral_angle=0.5, preload=0.25)
    evaluation = sb.DesignProblem(mechanism, workspace, [spring]).evaluate(np.zeros(0))
    reference = ReferencePotential(mechanism.model, [], [RefTorsional("theta", 3.0, 0.5, 0.25)])
    _assert_gradient(mechanism, workspace, evaluation, reference)


# ---------------------------------------------------------------------- linear parameters
def _linear_cases():
    a, b = sb.Anchor("universe", (0.02, 0.01, 0.12)), sb.Anchor("link1", (0.2, 0.0, 0.03))
    return [
        (
            sb.ExtensionSpring(
                a, b, stiffness=sb.Free(0, 500), free_length=0.05, initial_tension=sb.Free(0, 20), keep_tension=False
            ),
            ("stiffness", "initial_tension"),
        ),
        (
            sb.CompressionSpring(a, b, stiffness=sb.Free(0, 500), free_length=0.5, preload=sb.Free(0, 20)),
            ("stiffness", "preload"),
        ),
        (
            sb.GasSpring(a, b, stiffness=sb.Free(0, 500), free_length=0.5, preload=sb.Free(0, 20), mass=0.3),
            ("stiffness", "preload"),
        ),
        (sb.ConstantForceSpring(a, b, force=sb.Free(-20, 20)), ("force",)),
        (sb.ZeroFreeLengthSpring(a, b, stiffness=sb.Free(0, 500), mass=0.2), ("stiffness",)),
        (
            sb.TorsionalSpring("theta", stiffness=sb.Free(0, 5), neutral_angle=0.3, preload=sb.Free(-1, 1)),
            ("stiffness", "preload"),
        ),
    ]


@pytest.mark.parametrize("spring, linear", _linear_cases(), ids=lambda v: getattr(v, "kind", ""))
def test_declared_linear_parameters_enter_torque_and_potential_linearly(spring, linear):
    """``linear_parameters`` must be exactly the parameters tau and V are affine in: the
    solver fits them by linear least squares. Checked by superposition."""
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r2.urdf", gravity=9.8)
    workspace = sb.Workspace.grid(mechanism, 17)
    problem = sb.DesignProblem(mechanism, workspace, [spring])
    assert tuple(spring.linear_parameters) == linear
    names = problem.variables.names
    assert sorted(problem.model.linear_indices) == sorted(names.index(f"s1.{key}") for key in linear)
    rng = np.random.default_rng(3)
    lower, upper = problem.variables.bounds()
    x0 = rng.uniform(lower, upper)
    x1, x2 = x0.copy(), x0.copy()
    for key in linear:
        i = names.index(f"s1.{key}")
        x1[i], x2[i] = rng.uniform(lower[i], upper[i], 2)
    e1, e2, em = problem.evaluate(x1), problem.evaluate(x2), problem.evaluate(0.3 * x1 + 0.7 * x2)
    np.testing.assert_allclose(em.tau, 0.3 * e1.tau + 0.7 * e2.tau, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(em.potential, 0.3 * e1.potential + 0.7 * e2.potential, rtol=1e-12, atol=1e-12)


def test_coupled_mass_makes_stiffness_nonlinear():
    """m_s ∝ √k (docs/model.md §5): the torque is no longer linear in k, so k leaves the linear fit."""
    a, b = sb.Anchor("universe", (0, 0, 0.16)), sb.Anchor("link1", (0, 0, 0.3))
    coil = sb.CoilMass(coil_diameter=0.04, active_coils=80, wire_length=10.38, shear_modulus=81e9, density=7800)
    spring = sb.ExtensionSpring(
        a, b, stiffness=sb.Free(1, 500), free_length=0.1, initial_tension=sb.Free(0, 5), mass=coil
    )
    assert spring.linear_parameters == ("initial_tension",)
    spring.mass = None
    assert spring.linear_parameters == ("stiffness", "initial_tension")
    with pytest.raises(sb.InputError, match="stiffness > 0"):
        sb.ZeroFreeLengthSpring(a, b, stiffness=sb.Free(0, 500), mass=coil)


# ---------------------------------------------------------------------- records
def _record_cases():
    return [
        {
            "name": "g",
            "type": "gas",
            "a": {"body": "universe", "point": [0.05, 0, -0.05]},
            "b": {"body": "link1", "segment": {"start": [0.05, 0, 0], "end": [0.3, 0, 0]}},
            "stiffness": {"lower": 0, "upper": 1000},
            "free_length": 0.3,
            "preload": {"lower": 0, "upper": 100},
            "stays_compressed": True,
            "stroke": 0.2,
            "mass": 0.25,
            "max_force": 150.0,
        },
        {
            "name": "c",
            "type": "compression",
            "ideal": True,
            "a": {"body": "universe", "point": [0, 0, -0.1]},
            "b": {"body": "link1", "point": [0.1, 0, 0]},
            "stiffness": {"lower": 10, "upper": 5000},
            "free_length": 0.3,
            "preload": 0.0,
            "stays_compressed": False,
            "mass": {"coil_diameter": 0.03, "active_coils": 12, "material": "chrome_silicon"},
            "helical": {"material": "chrome_silicon", "index": 7, "min_active_coils": 4},
        },
        {
            "name": "e",
            "type": "extension",
            "ideal": True,
            "a": {"body": "universe", "point": [0, 0, 0.1]},
            "b": {"body": "link1", "point": [0.2, 0, 0]},
            "stiffness": {"lower": 1, "upper": 500},
            "free_length": {"lower": 0.03, "upper": 0.1},
            "initial_tension": 0.0,
            "keep_tension": True,
            "helical": {"material": "stainless_302"},
        },
        {
            "name": "f",
            "type": "constant_force",
            "a": {"body": "universe", "point": [0, 0, 0.2]},
            "b": {"body": "link1", "point": [0.2, 0, 0]},
            "force": {"lower": -30, "upper": 30},
            "min_length": 0.05,
        },
        {
            "name": "t",
            "type": "torsional",
            "joint": "theta",
            "stiffness": {"lower": 0, "upper": 5},
            "neutral_angle": {"lower": -3, "upper": 3},
            "preload": 0.0,
            "max_torque": 4.0,
            "max_deflection": 2.0,
        },
    ]


@pytest.mark.parametrize("record", _record_cases(), ids=lambda r: r["type"])
def test_records_round_trip(record):
    spring = sb.springs.spring_from_dict(record)
    again = sb.springs.spring_from_dict(json.loads(json.dumps(spring.to_dict())))
    assert again.to_dict() == spring.to_dict()
    key = record["type"] + (":ideal" if record.get("ideal") else "")
    assert type(again) is sb.springs.SPRING_TYPES[key]


def test_record_errors_name_the_key():
    with pytest.raises(sb.InputError, match="missing key 'joint'"):
        sb.springs.spring_from_dict({"type": "torsional", "stiffness": 1.0, "neutral_angle": 0.0})
    with pytest.raises(sb.InputError, match="unknown key 'helical'"):
        sb.springs.spring_from_dict(
            {
                "type": "gas",
                "a": {"body": "universe"},
                "b": {"body": "link1"},
                "stiffness": 1.0,
                "free_length": 0.3,
                "helical": {},
            }
        )
    with pytest.raises(sb.InputError, match="mass: unknown key 'diameter'"):
        sb.springs.spring_from_dict(
            {
                "type": "zero_free_length",
                "a": {"body": "universe"},
                "b": {"body": "link1"},
                "stiffness": 1.0,
                "mass": {"diameter": 0.1},
            }
        )
    with pytest.raises(sb.InputError, match="unknown spring material 'steel'"):
        sb.springs.spring_from_dict(
            {
                "type": "extension",
                "ideal": True,
                "a": {"body": "universe"},
                "b": {"body": "link1"},
                "stiffness": 1.0,
                "free_length": 0.1,
                "helical": {"material": "steel"},
            }
        )
    with pytest.raises(sb.InputError, match="stays_compressed: expected true or false"):
        sb.springs.spring_from_dict(
            {
                "type": "gas",
                "a": {"body": "universe"},
                "b": {"body": "link1"},
                "stiffness": 1.0,
                "free_length": 0.3,
                "stays_compressed": "yes",
            }
        )


def test_config_accepts_new_types_and_checks_joints(tmp_path):
    from springbalance.io.config import load_config

    base = {
        "mechanism": {"urdf": str(URDF / "single_link_r2.urdf"), "gravity": 9.8},
        "workspace": {"kind": "grid", "n": 31, "degrees": True, "ranges": {"theta": [0, 60]}},
        "springs": _record_cases(),
    }
    path = tmp_path / "config.json"
    path.write_text(json.dumps(base))
    config = load_config(path)
    assert [spring.kind for spring in config.springs] == [
        "gas",
        "compression",
        "extension",
        "constant_force",
        "torsional",
    ]
    base["springs"] = [{"type": "torsional", "joint": "knee", "stiffness": 1.0, "neutral_angle": 0.0}]
    path.write_text(json.dumps(base))
    with pytest.raises(sb.ConfigError, match=r"springs\[0\]\.joint: unknown joint 'knee'"):
        load_config(path)


def test_torsional_spring_needs_a_revolute_joint():
    urdf = (URDF / "single_link_r2.urdf").read_text().replace('type="revolute"', 'type="prismatic"')
    mechanism = sb.Mechanism.from_urdf_string(urdf)
    workspace = sb.Workspace.grid(mechanism, 5, ranges={"theta": (0, 0.1)})
    with pytest.raises(sb.InputError, match="prismatic"):
        sb.DesignProblem(mechanism, workspace, [sb.TorsionalSpring("theta", stiffness=1.0, neutral_angle=0.0)])


# ---------------------------------------------------------------------- results and reports
@pytest.fixture(scope="module")
def mixed_result():
    """A gas spring and a torsional spring sharing the load of the R2 link (θ ∈ [0°, 60°])."""
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r2.urdf", gravity=9.8)
    workspace = sb.Workspace.grid(mechanism, 61, ranges={"theta": (0, np.pi / 3)})
    springs = [sb.springs.spring_from_dict(record) for record in _record_cases() if record["name"] in ("g", "t")]
    return sb.solve(sb.DesignProblem(mechanism, workspace, springs, objective="rms"), starts=2)


def test_mixed_design_balances_and_respects_gas_spring_limits(mixed_result):
    metrics = mixed_result.metrics()
    assert metrics["joints"][0]["rms_reduction_percent"] > 90
    assert mixed_result.evaluation.max_violation <= 1e-6
    gas = mixed_result.spring("g")
    lengths = mixed_result.evaluation.lengths[:, 0]
    assert np.all(lengths <= gas["free_length"] + 1e-6)  # stays compressed
    assert np.all(lengths >= gas["free_length"] - 0.2 - 1e-6)  # stroke 0.2 m
    assert np.all(mixed_result.evaluation.tensions[:, 0] <= 0)  # it pushes


def test_result_records_and_report_show_fields_per_type(mixed_result):
    gas, torsional = mixed_result.spring("g"), mixed_result.spring("t")
    assert set(gas) >= {"a", "b", "stiffness", "free_length", "preload", "mass"} and "joint" not in gas
    assert gas["mass"] == 0.25
    assert torsional["joint"] == "theta" and "a" not in torsional and "mass" not in torsional
    assert set(torsional) >= {"stiffness", "neutral_angle", "preload"}
    text = mixed_result.table()
    assert "t (torsional)" in text and "joint: theta" in text
    assert "angle" in text and "torque" in text and "N·m/rad" in text
    assert "g (gas)" in text and "spring mass 0.25 kg" in text


def test_mixed_design_save_load_round_trip_is_exact(mixed_result, tmp_path):
    path = mixed_result.save(tmp_path / "design.json")
    loaded = sb.DesignResult.load(path)
    assert loaded.springs == mixed_result.springs
    np.testing.assert_array_equal(loaded.x, mixed_result.x)
    np.testing.assert_array_equal(loaded.evaluation.tau, mixed_result.evaluation.tau)
    assert [s.to_dict() for s in loaded.problem.springs] == [s.to_dict() for s in mixed_result.problem.springs]
    # a fixed copy of the design evaluates to the same torques
    again = mixed_result.on_workspace(mixed_result.problem.workspace)
    np.testing.assert_allclose(again.evaluation.tau, mixed_result.evaluation.tau, rtol=1e-13, atol=1e-13)


def test_free_length_interval_for_solver_starts():
    """The free lengths for which a spring's own length constraints hold at given lengths."""
    a, b = sb.Anchor("universe"), sb.Anchor("link1", (0.2, 0, 0))
    lengths = np.array([0.2, 0.35, 0.3])
    extension = sb.ExtensionSpring(a, b, stiffness=1.0, free_length=sb.Free(0.01, 1), max_stretch=1.5)
    assert extension.free_length_interval(lengths) == pytest.approx((0.35 / 1.5, 0.2))
    gas = sb.GasSpring(a, b, stiffness=1.0, free_length=sb.Free(0.01, 1), stroke=0.2)
    assert gas.free_length_interval(lengths) == pytest.approx((0.35, 0.4))
    assert sb.ZeroFreeLengthSpring(a, b, stiffness=1.0).free_length_interval(lengths) == (-np.inf, np.inf)
