"""The largest Python files and the longest functions of the package and the studies, in lines
(tests/test_sizes.py holds them under its limits).

    python experiments/tools/sizes.py [--top N]
"""

from __future__ import annotations

import argparse
import ast

from realikea.files import WORKSPACE

FOLDERS = ("realikea", "experiments")


def sources(*folders: str):
    """(repository-relative path, text) of every Python file under the folders."""
    for folder in folders:
        for path in sorted((WORKSPACE / folder).rglob("*.py")):
            yield path.relative_to(WORKSPACE).as_posix(), path.read_text()


def file_lengths(*folders: str) -> dict[str, int]:
    """Lines per file."""
    return {name: len(text.splitlines()) for name, text in sources(*folders)}


def function_lengths(*folders: str) -> dict[str, int]:
    """Lines per function (`path:name`, nested ones too), decorators left out."""
    found = {}
    for name, text in sources(*folders):
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                found[f"{name}:{node.name}"] = node.end_lineno - node.lineno + 1
    return found


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--top", type=int, default=5)
    args = parser.parse_args()
    for title, lengths in (
        ("files", file_lengths(*FOLDERS)),
        ("functions", function_lengths(*FOLDERS)),
    ):
        print(f"longest {title}:")
        for name, lines in sorted(lengths.items(), key=lambda kv: -kv[1])[: args.top]:
            print(f"  {lines:5d}  {name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
