"""Markdown tables from cells, so every report writes them the same way."""

from __future__ import annotations

from collections.abc import Iterable, Sequence


def table(header: Sequence[str], align: str, rows: Iterable[Sequence[str]]) -> list[str]:
    """A markdown table's lines: the header, the rule (`align`: l or r per column) and a line per
    row of cells."""
    if len(align) != len(header):
        raise ValueError(f"align {align!r} names {len(align)} columns, the header {len(header)}")
    rule = "|" + "|".join("---:" if a == "r" else "---" for a in align) + "|"
    lines = ["| " + " | ".join(header) + " |", rule]
    for row in rows:
        if len(row) != len(header):
            raise ValueError(f"a row of {len(row)} cells under {len(header)} columns: {row}")
        lines.append("| " + " | ".join(row) + " |")
    return lines
