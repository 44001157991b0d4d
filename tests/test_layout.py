"""The layout's own numbers: no import cycle inside a package, no module or function too long.

The layer order between packages (missions -> behaviours -> nav -> robots -> sim, and inside
missions cli -> testing | campaigns -> run -> language) is import-linter's contracts in
``pyproject.toml`` (``lint-imports``, run by ``.ci/run``); this file checks what a reader feels
in every module: one can read a package from its leaves up, and no module or function is too
long to hold in one's head.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import grimp
import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ("missions", "behaviours", "nav", "robots", "sim")
MAX_MODULE_LINES = 500
MAX_FUNCTION_LINES = 80
COMPILERS = ("numba", "njit", "jit")
"""Decorators of compiled kernels, the functions the length limit does not apply to."""


def _sources() -> list[Path]:
    return sorted(path for package in PACKAGES for path in (REPO / package).rglob("*.py"))


def _functions(tree: ast.AST) -> Iterator[ast.FunctionDef | ast.AsyncFunctionDef]:
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            yield node


def _compiled(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    return any(
        any(name in ast.unparse(decorator) for name in COMPILERS)
        for decorator in function.decorator_list
    )


def test_no_module_is_longer_than_500_lines() -> None:
    long = {
        str(path.relative_to(REPO)): lines
        for path in _sources()
        if (lines := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES
    }
    assert long == {}


def test_no_function_but_a_compiled_kernel_is_longer_than_80_lines() -> None:
    long: dict[str, int] = {}
    for path in _sources():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for function in _functions(tree):
            lines = (function.end_lineno or function.lineno) - function.lineno + 1
            if lines > MAX_FUNCTION_LINES and not _compiled(function):
                long[f"{path.relative_to(REPO)}:{function.lineno} {function.name}"] = lines
    assert long == {}


@pytest.fixture(scope="module")
def graph() -> grimp.ImportGraph:
    return grimp.build_graph("baobab", include_external_packages=False)


def _cycles(graph: grimp.ImportGraph, package: str) -> list[list[str]]:
    """The import cycles between the children of ``package`` (a child stands for its subtree)."""
    prefix = package + "."

    def child(module: str) -> str | None:
        return module[len(prefix) :].split(".")[0] if module.startswith(prefix) else None

    edges: dict[str, set[str]] = {}
    for module in graph.find_descendants(package):
        importer = child(module)
        for imported in graph.find_modules_directly_imported_by(module):
            target = child(imported)
            if importer is not None and target is not None and target != importer:
                edges.setdefault(importer, set()).add(target)
    return _strongly_connected(edges)


def _strongly_connected(edges: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's algorithm: the groups of two or more nodes that reach each other."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    groups: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for target in sorted(edges.get(node, ())):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            group = []
            while True:
                member = stack.pop()
                group.append(member)
                if member == node:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    for node in sorted(edges):
        if node not in index:
            visit(node)
    return groups


def _packages(graph: grimp.ImportGraph) -> list[str]:
    names = [f"baobab.{package}" for package in PACKAGES]
    names += [m for name in names for m in graph.find_descendants(name)]
    return sorted(name for name in set(names) if graph.find_children(name))


def test_no_package_has_an_import_cycle_between_its_modules(graph: grimp.ImportGraph) -> None:
    cycles = {package: found for package in _packages(graph) if (found := _cycles(graph, package))}
    assert cycles == {}


def test_the_cycle_check_sees_a_cycle() -> None:
    assert _strongly_connected({"a": {"b"}, "b": {"c", "a"}, "c": set()}) == [["a", "b"]]
