"""The package holds general tools only: no module under realikea/ is named after a study (a
folder under experiments/ that holds training runs), and none hard-codes a path under
experiments/ in its code (docstrings and comments may link a study's README for the measurements
behind a choice). Folders named after a component they exercise (experiments/kitchen/, .../interop/)
hold no runs and are no study."""

from __future__ import annotations

import ast

from realikea.files import WORKSPACE

PACKAGE = WORKSPACE / "realikea"
STUDIES = sorted(
    {
        p.relative_to(WORKSPACE / "experiments").parts[0]
        for p in WORKSPACE.glob("experiments/**/.hydra")
    }
)


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the docstring nodes of a module, its classes and functions."""
    owners = [
        n for n in ast.walk(tree) if isinstance(n, ast.Module | ast.ClassDef | ast.FunctionDef)
    ]
    return {
        id(owner.body[0].value)
        for owner in owners
        if owner.body
        and isinstance(owner.body[0], ast.Expr)
        and isinstance(owner.body[0].value, ast.Constant)
    }


def test_no_module_or_package_under_realikea_is_named_after_a_study():
    named = [
        str(p.relative_to(WORKSPACE))
        for p in PACKAGE.rglob("*")
        if (p.is_dir() or p.suffix == ".py") and p.stem in STUDIES
    ]
    assert STUDIES and not named


def test_no_code_under_realikea_hard_codes_a_path_under_experiments():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text())
        docstrings = _docstrings(tree)
        found += [
            f"{path.relative_to(WORKSPACE)}:{node.lineno}: {node.value!r}"
            for node in ast.walk(tree)
            if isinstance(node, ast.Constant)
            and isinstance(node.value, str)
            and id(node) not in docstrings
            and "experiments/" in node.value
        ]
    assert not found, "\n".join(found)
