"""The package's layers point one way: no import cycles, and no module importing a layer above it.

Every `import` and `from ... import` of a project module counts: at module level, inside a
function (an edge when it runs), and under `if TYPE_CHECKING:` (an edge for every reader and type
checker, even if it never runs).
"""

from __future__ import annotations

import ast
from pathlib import Path

import realikea

PACKAGE = Path(realikea.__file__).parent
# bottom to top; a module may import its own layer and the layers below it
LAYERS = (
    ("errors", "files", "spawn", "rewards", "config", "provenance", "sources", "markdown"),
    ("sim",),
    ("assets", "tasks", "datasets"),
    ("fidelity",),  # measures the built library's meshes
    ("export",),  # writes the library with each part's fidelity certificate
    ("interop",),
    ("pool",),
    ("policies",),
    ("eval", "training", "runs"),
    ("reports",),
    ("cli",),
)
RANK = {name: i for i, layer in enumerate(LAYERS) for name in layer}


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported(source: str) -> set[str]:
    """Every module name an `import` or absolute `from ... import` in `source` may refer to."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names |= {f"{node.module}.{a.name}" for a in node.names} | {node.module}
        elif isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
    return names


def import_graph() -> dict[str, set[str]]:
    """module -> the project modules it imports (a package import counts as its __init__)."""
    paths = {module_name(p): p for p in PACKAGE.rglob("*.py")}
    return {
        name: {t for t in imported(path.read_text()) if t in paths and t != name}
        for name, path in paths.items()
    }


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def layer(module: str) -> str:
    return module.split(".")[1] if "." in module else "cli"


def test_the_cycle_finder_finds_a_cycle():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_imports_under_type_checking_and_in_functions_count():
    source = (
        "from typing import TYPE_CHECKING\n"
        "if TYPE_CHECKING:\n    from realikea.assets.catalog import Part\n"
        "def f():\n    import realikea.sim.scene\n"
    )
    assert {"realikea.assets.catalog", "realikea.sim.scene"} <= imported(source)


def test_no_import_cycles():
    assert cycles(import_graph()) == []


def test_every_subpackage_has_a_layer():
    assert {layer(m) for m in import_graph() if m != "realikea"} <= set(RANK)


def test_imports_point_down_the_layers():
    upward = sorted(
        f"{a} -> {b}"
        for a, targets in import_graph().items()
        for b in targets
        if a != "realikea" and RANK[layer(b)] > RANK[layer(a)]
    )
    assert upward == []
