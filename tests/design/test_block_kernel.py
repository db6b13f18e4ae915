"""The block kernel (design/block_kernel.py) gives bit for bit CasADi's own compiled result."""

import numpy as np
import pytest

from springbalance.design.block_kernel import SOURCE_ATTRIBUTE, block_kernel, block_kernel_code
from springbalance.design.solvers.residuals import _LeastSquaresResiduals
from springbalance.design.torque_model import BlockEvaluator, compiler_available
from springbalance.io.config import load_config

pytestmark = pytest.mark.skipif(not compiler_available(), reason="no C compiler on PATH: the kernel is C")


@pytest.fixture(scope="module")
def coil_problem(tmp_path_factory):
    """The two-link demo (three helical coils: square roots, powers, stress and hook rows) on 2,100
    samples, a number that is not a multiple of the kernel's 4 lanes nor of a block."""
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    text = (root / "examples" / "two_link.yaml").read_text().replace("n: 128", "n: 2100")
    text = text.replace("../urdf/", str(root / "urdf") + "/")
    path = tmp_path_factory.mktemp("kernel") / "two_link.yaml"
    path.write_text(text)
    return load_config(path).problem


def test_kernel_outputs_equal_casadi_bit_for_bit(coil_problem):
    residuals = _LeastSquaresResiduals(coil_problem)
    function = residuals.function
    assert block_kernel(function, coil_problem.workspace.size) is not None  # it is built for this function
    assert "vector_size(32)" in block_kernel_code(getattr(function, SOURCE_ATTRIBUTE))  # 4 doubles per vector
    with_kernel = BlockEvaluator(function, coil_problem.data, kernel=True)
    without = BlockEvaluator(function, coil_problem.data, kernel=False)
    rng = np.random.default_rng(3)
    for z in rng.random((3, coil_problem.variables.size)):
        for a, b in zip(with_kernel.evaluate(z), without.evaluate(z)):
            assert a.shape == b.shape
            assert np.array_equal(a, b), float(np.max(np.abs(a - b)))


def test_normal_equations_equal_with_and_without_kernel(coil_problem, monkeypatch):
    """The solver's sums JᵀJ, Jᵀr, rᵀr (two threads by default) equal those of CasADi's map."""
    z = np.full(coil_problem.variables.size, 0.4)
    fast = _LeastSquaresResiduals(coil_problem)
    fast.evaluator = BlockEvaluator(fast.function, coil_problem.data, kernel=True)
    plain = _LeastSquaresResiduals(coil_problem)
    plain.evaluator = BlockEvaluator(plain.function, coil_problem.data, kernel=False)
    for a, b in zip(fast.normal_equations(z), plain.normal_equations(z)):
        assert np.array_equal(a, b)


def test_small_workspaces_keep_casadi_map(coil_problem):
    function = _LeastSquaresResiduals(coil_problem).function
    assert block_kernel(function, 128) is None


@pytest.mark.parametrize("text, expected", [("1", 1), ("2", 2), ("8", 2)])
def test_threads_from_the_environment(monkeypatch, text, expected):
    from springbalance.design.torque_model import THREADS_ENV, evaluation_threads

    monkeypatch.setenv(THREADS_ENV, text)
    assert evaluation_threads() == expected


@pytest.mark.parametrize("text", ["0", "-1", "two", "1.5"])
def test_bad_thread_counts_name_the_variable(monkeypatch, text):
    from springbalance.design.torque_model import THREADS_ENV, evaluation_threads
    from springbalance.errors import InputError

    monkeypatch.setenv(THREADS_ENV, text)
    with pytest.raises(InputError, match=f"{THREADS_ENV} must be an integer ≥ 1, got"):
        evaluation_threads()


def test_one_thread_holds_within_its_block_only(monkeypatch):
    from springbalance.design.torque_model import THREADS_ENV, evaluation_threads, one_thread

    monkeypatch.delenv(THREADS_ENV, raising=False)
    before = evaluation_threads()
    with one_thread():
        assert evaluation_threads() == 1
    assert evaluation_threads() == before


def test_a_function_the_kernel_cannot_take_keeps_casadi_map(coil_problem):
    """An external (already compiled) function is not SX: no kernel of its own; a function that did not come
    from compiled() gets none either, and its evaluator runs CasADi's map."""
    from springbalance.design.block_kernel import Unsupported, _compile_kernel

    function = _LeastSquaresResiduals(coil_problem).function  # a casadi.external
    with pytest.raises(Unsupported, match="not an SX function"):
        block_kernel_code(function)
    assert _compile_kernel(function) is None
    assert block_kernel(coil_problem.model.sample, coil_problem.workspace.size) is None
    assert BlockEvaluator(coil_problem.model.sample, coil_problem.data)._kernel is None
