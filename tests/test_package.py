"""The package's API and its lazy import (``import springbalance`` loads no subpackage nor heavy dependency).

Each check that is about what an import loads runs in a fresh interpreter.
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys

import pytest

import springbalance as sb

HEAVY = ("numpy", "casadi", "pinocchio", "pydantic", "springbalance.design", "springbalance.model.mechanism")


#: optional dependencies that only some commands need; the command line imports them when a command runs
#: (meshcat joins the list once springbalance.viz imports it lazily)
OPTIONAL = ("matplotlib", "mujoco", "dask", "distributed", "yourdfpy", "trimesh", "scipy.optimize")


def _loaded(code: str, modules: tuple[str, ...] = HEAVY) -> list[str]:
    """The modules of ``modules`` (default :data:`HEAVY`) loaded after ``code`` ran in a fresh interpreter."""
    probe = f"{code}\nimport json, sys\nprint(json.dumps([m for m in {modules!r} if m in sys.modules]))"
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout.strip().splitlines()[-1])


def test_import_loads_no_subpackage_nor_heavy_dependency():
    assert _loaded("import springbalance") == []


def test_errors_and_version_need_no_subpackage():
    assert _loaded("import springbalance as sb\nsb.InputError, sb.ConfigError, sb.SolverError, sb.__version__") == []


def test_first_use_loads_what_it_needs():
    assert set(_loaded("import springbalance as sb\nsb.Mechanism")) >= {"numpy", "pinocchio"}
    # the design problem and the spring laws do not need pydantic (the config schema does)
    assert "pydantic" not in _loaded(
        "import springbalance as sb\nsb.DesignProblem, sb.ExtensionSpring, sb.DesignResult"
    )


def test_the_command_line_help_loads_no_optional_dependency():
    # the command modules import their first-party modules at module level (so --help loads numpy, casadi,
    # pinocchio and pydantic); the optional heavy dependencies stay lazy
    code = "from springbalance.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass"
    assert _loaded(code, OPTIONAL) == []


@pytest.mark.parametrize("name", sb.__all__)
def test_every_public_name_resolves_to_its_definition(name):
    value = getattr(sb, name)
    assert value is not None
    if name in ("exact", "constraints"):
        assert value is importlib.import_module(f"springbalance.{'design' if name == 'exact' else 'springs'}.{name}")
    elif hasattr(value, "__module__") and isinstance(value, type):
        assert getattr(importlib.import_module(value.__module__), value.__qualname__) is value


def test_from_imports_and_dir():
    from springbalance import DesignProblem, Mechanism, constraints, exact  # noqa: F401
    from springbalance.design.problem import DesignProblem as defined

    assert DesignProblem is defined and sb.Mechanism is Mechanism
    assert set(sb.__all__) <= set(dir(sb))
    assert sb.springs.spring_from_dict is importlib.import_module("springbalance.springs.records").spring_from_dict
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        sb.nothing  # noqa: B018


def test_a_design_problem_imported_alone_still_returns_design_results():
    # the deprecated DesignProblem.result imports the results layer itself: the problem module imported by
    # itself (as in a worker process) still returns a DesignResult, with a DeprecationWarning
    code = """
import warnings
import numpy as np
from springbalance.design.problem import DesignProblem
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import ZeroFreeLengthSpring
from springbalance.springs.params import Anchor
mechanism = Mechanism.from_robot("ur5")
spring = ZeroFreeLengthSpring(Anchor("universe", [0, 0, 0.5]), Anchor("forearm_link", [0.1, 0, 0]), "s", stiffness=100)
problem = DesignProblem(mechanism, Workspace.sobol(mechanism, 8, seed=1), [spring])
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    result = problem.result(np.zeros(problem.variables.size))
assert any(issubclass(w.category, DeprecationWarning) for w in caught)
print(type(result).__qualname__)
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip().splitlines()[-1] == "DesignResult"
