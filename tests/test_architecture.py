"""The package's shape, checked on the source: no import cycle of any kind, no first-party import inside a
function, no ``importlib`` on the package's own modules, modules and functions of a readable size.

``lint-imports`` (tests/test_layers.py) checks the layers between the subpackages; these tests read every
module with :mod:`ast`, so that an import under ``TYPE_CHECKING`` or inside a function counts as an edge
too. The only exceptions are listed here, each with its reason.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SOURCE = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "springbalance"
#: the deprecated shims of DesignProblem (removed in 0.3) reach up to the pipeline and the results
DEPRECATED_SHIMS = {
    ("springbalance.design.problem_deprecated", "springbalance.pipeline.run"),
    ("springbalance.design.problem_deprecated", "springbalance.results.result"),
}
#: generated-code templates may be long (a function's length is its code, without signature and docstring)
LONG_FUNCTIONS_ALLOWED = {("springbalance.design.block_kernel", "block_kernel_code")}
MAX_MODULE_LINES = 450
MAX_FUNCTION_LINES = 60


def _modules() -> dict[str, Path]:
    modules = {}
    for path in sorted((SOURCE / PACKAGE).rglob("*.py")):
        parts = list(path.relative_to(SOURCE).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        modules[".".join(parts)] = path
    return modules


MODULES = _modules()


def _target(name: str) -> str | None:
    """The module of ``name`` (a module, or a name inside one)."""
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return name or None


def _imports(module: str) -> list[tuple[str, bool, int]]:
    """``(imported module, inside a function, line)`` of every first-party import of ``module``."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            inside = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef))
            names: list[str] = []
            if isinstance(child, ast.Import):
                names = [alias.name for alias in child.names]
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:
                    parts = package.split(".")[: len(package.split(".")) - child.level + 1]
                    base = ".".join(parts + ([base] if base else []))
                names = [f"{base}.{alias.name}" for alias in child.names] or [base]
            for name in names:
                target = _target(name) if name.startswith(PACKAGE) else None
                if target is not None and target != module:
                    found.append((target, inside, child.lineno))
            visit(child, inside)

    visit(ast.parse(path.read_text()), False)
    return found


def _graph() -> dict[str, set[str]]:
    """Module → the modules it imports (a package's ``__init__`` only when imported as such)."""
    graph: dict[str, set[str]] = {}
    for module in MODULES:
        graph[module] = {
            target
            for target, _, _ in _imports(module)
            if (module, target) not in DEPRECATED_SHIMS and MODULES[target].name != "__init__.py"
        }
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def connect(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for target in graph[node]:
            if target not in index:
                connect(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for node in graph:
        if node not in index:
            connect(node)
    return components


def _body_lines(function: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """Lines of a function's code: from its first statement after the docstring to its end (the docstring
    states the math and the units, and the formatter puts one parameter per line of a long signature)."""
    body = function.body
    if len(body) > 1 and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    return (function.end_lineno or function.lineno) - body[0].lineno + 1


def test_no_import_cycle_of_any_kind():
    assert _cycles(_graph()) == []


def test_a_cycle_through_a_type_checking_import_is_found():
    graph = _graph()
    graph["springbalance.model.mechanism"] = graph["springbalance.model.mechanism"] | {"springbalance.results.result"}
    cycles = _cycles(graph)
    assert cycles and any("springbalance.model.mechanism" in cycle for cycle in cycles)


def test_no_first_party_import_inside_a_function():
    inside = [
        (module, target, line)
        for module in MODULES
        for target, in_function, line in _imports(module)
        if in_function and (module, target) not in DEPRECATED_SHIMS
    ]
    assert inside == []


def test_importlib_only_in_the_lazy_package_init():
    users = [module for module, path in MODULES.items() if "importlib" in path.read_text()]
    assert users == [PACKAGE]


def test_modules_and_functions_are_of_a_readable_size():
    long_modules = {
        module: len(path.read_text().splitlines())
        for module, path in MODULES.items()
        if len(path.read_text().splitlines()) > MAX_MODULE_LINES
    }
    long_functions = []
    for module, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                length = _body_lines(node)
                if length > MAX_FUNCTION_LINES and (module, node.name) not in LONG_FUNCTIONS_ALLOWED:
                    long_functions.append((module, node.name, length))
    assert long_modules == {} and long_functions == []


@pytest.mark.parametrize("module", sorted(MODULES))
def test_every_module_has_a_docstring(module):
    assert ast.get_docstring(ast.parse(MODULES[module].read_text())), f"{module} has no module docstring"
