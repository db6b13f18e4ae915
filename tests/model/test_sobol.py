"""Scrambled Sobol points without scipy.stats: bit for bit SciPy's, so designs do not change."""

import warnings

import numpy as np
import pytest
from scipy.stats import qmc

import springbalance as sb
from springbalance.design.solvers import start_points
from springbalance.model.sobol import ScrambledSobol, sobol_engine


def _scipy(d, seed):
    return qmc.Sobol(d=d, scramble=True, seed=np.random.default_rng(seed))


@pytest.mark.parametrize("d", [1, 2, 6, 13, 40])
@pytest.mark.parametrize("seed", [0, 1, 12345])
def test_points_equal_scipy_bit_for_bit_over_successive_draws(d, seed):
    ours, theirs = sobol_engine(d, np.random.default_rng(seed)), _scipy(d, seed)
    assert isinstance(ours, ScrambledSobol)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # SciPy warns that 7 and 100 are not powers of two
        for n in (1, 7, 64, 100, 1024):
            assert np.array_equal(ours.random(n), theirs.random(n))


def test_the_generator_is_used_as_scipy_uses_it():
    # SciPy draws the scramble from a child of the generator's seed sequence: the generator's own
    # stream is untouched, and what it draws afterwards is the same
    ours, theirs = np.random.default_rng(5), np.random.default_rng(5)
    sobol_engine(3, ours).random(8)
    qmc.Sobol(d=3, scramble=True, seed=theirs).random(8)
    assert np.array_equal(ours.random(4), theirs.random(4))


def test_workspace_and_start_points_are_unchanged():
    mechanism = sb.Mechanism.from_robot("ur5")
    ranges = {"shoulder_pan_joint": [-1.0, 1.0], "elbow_joint": [0.0, 2.0]}
    workspace = sb.Workspace.sobol(mechanism, 1000, ranges=ranges, seed=3)
    sampler = _scipy(mechanism.nv, 3)
    lower = np.array([joint.lower for joint in mechanism.joints])
    upper = np.array([joint.upper for joint in mechanism.joints])
    for name, (lo, hi) in ranges.items():
        lower[mechanism.joint(name).index_v], upper[mechanism.joint(name).index_v] = lo, hi
    expected = lower + sampler.random(1024) * (upper - lower)
    assert np.array_equal(workspace.joint_values, expected[:1000])

    spring = sb.ExtensionSpring(
        sb.Anchor("universe", sb.Free([-0.3] * 3, [0.3] * 3)),
        sb.Anchor("forearm_link", sb.Free([-0.3] * 3, [0.3] * 3)),
        stiffness=sb.Free(0, 5000),
        free_length=sb.Free(0.05, 1.0),
    )
    problem = sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, 16, seed=1), [spring])
    points = start_points(problem, 8, seed=7)
    assert np.array_equal(points[1:], _scipy(problem.variables.size, 7).random(8)[:7])


def test_import_does_not_load_scipy_stats_or_optimize():
    import subprocess
    import sys

    code = (
        "import sys, springbalance; springbalance.DesignProblem, springbalance.DesignResult; "  # the lazy names loaded
        "print(sorted(m for m in ('scipy.stats', 'scipy.optimize') if m in sys.modules))"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"
