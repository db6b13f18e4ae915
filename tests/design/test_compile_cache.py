"""The compiled residual cached on disk: a second process skips the compiler, writes are atomic."""

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from springbalance.design import compile_cache
from springbalance.design.torque_model import compiler_available

pytestmark = pytest.mark.skipif(not compiler_available(), reason="no C compiler")

# builds a small problem's compiled residual and prints what the cache did
SCRIPT = textwrap.dedent("""
    import json, sys
    import springbalance as sb
    from springbalance.design import compile_cache
    from springbalance.design.solvers.residuals import _LeastSquaresResiduals
    mechanism = sb.Mechanism.from_urdf("urdf/two_link_planar.urdf")
    spring = sb.ExtensionSpring(sb.Anchor("universe", sb.Free([-0.2, 0, 0], [0.2, 0, 0.3])),
                                sb.Anchor("link2", sb.Free([0.0, 0, 0], [0.4, 0, 0])),
                                stiffness=sb.Free(0, 800), free_length=sb.Free(0.05, 0.5), name=sys.argv[1])
    problem = sb.DesignProblem(mechanism, sb.Workspace.sobol(mechanism, 32, seed=0), [spring])
    residuals = _LeastSquaresResiduals(problem)
    r, J = residuals.residuals_and_jacobian([0.3] * problem.variables.size)
    print(json.dumps({"hits": compile_cache.STATS.hits, "compiles": compile_cache.STATS.compiles,
                      "r": float(r @ r), "external": residuals.function.class_name()}))
""")


def _run(cache, name="s1", extra=None, wait=True):
    env = {**os.environ, "SPRINGBALANCE_CACHE_DIR": str(cache), **(extra or {})}
    process = subprocess.Popen(
        [sys.executable, "-c", SCRIPT, name],
        cwd=os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    if not wait:
        return process
    return _result(process)


def _result(process):
    import json

    out, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    return json.loads(out.strip().splitlines()[-1])


def _libraries(cache):
    return sorted(name for name in os.listdir(cache / "compiled") if not name.startswith("tmp-"))


def test_a_second_process_loads_the_library_without_compiling(tmp_path):
    first = _run(tmp_path)
    assert (first["compiles"], first["hits"]) == (1, 0)
    assert first["external"] == "External"
    second = _run(tmp_path)
    assert (second["compiles"], second["hits"]) == (0, 1)
    assert second["r"] == first["r"]
    assert len(_libraries(tmp_path)) == 1
    # other flags are another key: compiled again, the same numbers
    other_flags = _run(tmp_path, extra={"SPRINGBALANCE_CFLAGS": "-O1"})
    assert other_flags["compiles"] == 1 and other_flags["r"] == pytest.approx(first["r"], rel=1e-12)
    assert len(_libraries(tmp_path)) == 2


def test_two_processes_compiling_at_once_both_succeed(tmp_path):
    processes = [_run(tmp_path, wait=False) for _ in range(2)]
    results = [_result(process) for process in processes]
    assert results[0]["r"] == results[1]["r"]
    assert len(_libraries(tmp_path)) == 1
    assert not [name for name in os.listdir(tmp_path / "compiled") if name.startswith("tmp-")]


def test_a_damaged_library_is_compiled_again(tmp_path):
    first = _run(tmp_path)
    (library,) = _libraries(tmp_path)
    (tmp_path / "compiled" / library).write_bytes(b"not a shared library")
    again = _run(tmp_path)
    assert again["compiles"] == 1 and again["r"] == first["r"]


def test_the_compiled_function_matches_the_virtual_machine(monkeypatch, tmp_path):
    import casadi as ca

    monkeypatch.setenv("SPRINGBALANCE_CACHE_DIR", str(tmp_path))
    x = ca.SX.sym("x", 3)
    data = ca.SX.sym("d", 2)
    function = ca.Function(
        "cache_probe",
        [x, data],
        [ca.sin(x) * data[0] + ca.sqrt(data[1]) * x[0] ** 3, ca.jacobian(ca.sum1(ca.exp(x)) * data[1], x)],
    )
    compiled = compile_cache.compile_function(function)
    assert compiled.class_name() == "External"
    arguments = [np.array([0.3, -1.2, 2.0]), np.array([1.5, 2.5])]
    for ours, theirs in zip(compiled(*arguments), function(*arguments)):
        assert np.allclose(np.array(ours), np.array(theirs), rtol=1e-14, atol=0)
    assert any(name.startswith("cache_probe-") for name in os.listdir(tmp_path / "compiled"))


def test_the_cache_folder_is_the_users_unless_overridden(monkeypatch, tmp_path):
    import platformdirs

    monkeypatch.setenv("SPRINGBALANCE_CACHE_DIR", str(tmp_path))
    assert compile_cache.cache_dir() == os.path.join(str(tmp_path), "compiled")
    monkeypatch.delenv("SPRINGBALANCE_CACHE_DIR")
    assert compile_cache.cache_dir() == os.path.join(
        platformdirs.user_cache_dir("springbalance", appauthor=False), "compiled"
    )


def test_the_key_covers_code_compiler_and_flags():
    compiler = compile_cache.compiler()
    key = compile_cache.cache_key("int f;", compiler, ("-O3",))
    assert key == compile_cache.cache_key("int f;", compiler, ("-O3",))
    assert key != compile_cache.cache_key("int g;", compiler, ("-O3",))
    assert key != compile_cache.cache_key("int f;", compiler, ("-O2",))
    assert key != compile_cache.cache_key("int f;", sys.executable, ("-O3",))
