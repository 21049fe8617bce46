"""The report's section on phase maps: each map's heat maps and its CoACD − hull differences."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from realikea.errors import RealIkeaError
from realikea.reports.multiplicity import holm_lines
from realikea.reports.phase_map import difference_grid_lines, differences, read_cells
from realikea.runs.records import command_overrides

from .tables import relative


def phase_map_lines(maps: Sequence[Path], out: Path) -> list[str]:
    """Markdown: each phase map (a directory `phase_map.py` wrote: cells.jsonl, phase_map.md,
    phase_map.png) with what it maps, its heat maps and its CoACD − hull differences."""
    missing = [
        m / name
        for m in maps
        for name in ("cells.jsonl", "phase_map.md", "phase_map.png")
        if not (m / name).is_file()
    ]
    if missing:
        raise RealIkeaError(
            f"not a phase map (phase_map.py writes these): {', '.join(map(str, missing))}"
        )
    mapped = {folder: read_cells(folder / "cells.jsonl") for folder in maps}
    empty = [str(folder / "cells.jsonl") for folder, cells in mapped.items() if not cells]
    if empty:
        raise RealIkeaError(f"phase map without cells: {', '.join(empty)}")
    lines = ["## Friction-trap phase maps", ""] if maps else []
    for folder, cells in mapped.items():
        records = list(cells.values())
        policies = ", ".join(dict.fromkeys(r["policy"] for r in records))
        cones = ", ".join(dict.fromkeys(r["cone"] for r in records))
        episodes = "/".join(map(str, sorted({r["episodes"] for r in records})))
        splits = "/".join(sorted({r.get("split", "all") for r in records}))
        resistances = "/".join(sorted({r["resistance"] for r in records}))
        table = relative(folder / "phase_map.md", out)
        checkpoints = {
            r["policy"]: token.removeprefix("policy.path=")
            for r in records
            if "command" in r
            for token in command_overrides(r["command"])
            if token.startswith("policy.path=")
        }
        lines += [
            f"### {relative(folder, out)}",
            "",
            f"Policies {policies}; {cones} cones; {len(records)} cells of {episodes} episodes, "
            f"{splits} parts, resistance {resistances}. "
            f"Every cell's success and slip ratio: [phase_map.md]({table}).",
            "",
            *[f"- {policy}: `{path}`" for policy, path in checkpoints.items()],
            "",
            f"![{folder.name}]({relative(folder / 'phase_map.png', out)})",
            "",
            *difference_grid_lines(cells, "coacd", "hull"),
        ]
        family = list(differences(cells, "coacd", "hull").values())
        if family:
            lines += ["", *holm_lines(family, "Every cell of this map at once (Holm)", "####")]
    return lines
