"""The largest absolute difference between the actors of two checkpoints (their network and
their observation normaliser apart), or between each stage folder of a kept run and the folder
of the same name in the runs its stages were copied from (experiments/generalist/copy_stages.py);
with `--remove-copies`, the stage folders that are exact copies (every actor tensor of every
checkpoint equal) are deleted, the newly trained ones kept.

    python experiments/tools/weight_difference.py A.pt B.pt
    python experiments/tools/weight_difference.py --stages RUN SOURCE... [--remove-copies]

A later SOURCE's folder of a name is the one compared, as copy_stages.py copies it. Every path is
checked before anything is read or removed. Exit 0, or 2 on bad input.
"""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path

from realikea.errors import RealIkeaError
from realikea.policies.checkpoint import load_saved

STAGE_PREFIX = "teacher_"  # a pipeline's stage folders (copy_stages.py's)
NORMALISER = "obs_normalizer."  # the actor's observation normaliser (its mean, var, count)


def tensor_differences(a: Path, b: Path) -> dict[str, float]:
    """max |a - b| of each actor tensor (network and normaliser) of the two checkpoints; refuses
    two actors of different layouts."""
    actors = [load_saved(path)["actor_state_dict"] for path in (a, b)]
    shapes = [{k: tuple(v.shape) for k, v in actor.items()} for actor in actors]
    if shapes[0] != shapes[1]:
        raise RealIkeaError(f"{a} and {b}: the actors' layouts differ")
    first, second = actors
    return {k: float((first[k].double() - second[k].double()).abs().max()) for k in first}


def summary(deltas: dict[str, float]) -> str:
    """The largest difference over the network's tensors and over the normaliser's."""
    network = max((d for k, d in deltas.items() if not k.startswith(NORMALISER)), default=0.0)
    normaliser = max((d for k, d in deltas.items() if k.startswith(NORMALISER)), default=0.0)
    return f"max |Δw| {network:.3g} over the network, {normaliser:.3g} over the normaliser"


def stage_sources(run: Path, sources: list[Path]) -> dict[str, Path | None]:
    """Each stage folder of `run` and the source run's folder of its name (the last source that
    has one), or None for a stage no source has."""
    found: dict[str, Path | None] = {}
    for stage in sorted(p for p in run.glob(f"{STAGE_PREFIX}*") if p.is_dir()):
        having = [s / stage.name for s in sources if (s / stage.name).is_dir()]
        found[stage.name] = having[-1] if having else None
    return found


def folder_difference(stage: Path, source: Path) -> float | None:
    """max |Δw| over every checkpoint of `stage` against the same-named one in `source`; None
    when the two folders hold different checkpoint names."""
    names = sorted(p.name for p in stage.glob("*.pt"))
    if not names or names != sorted(p.name for p in source.glob("*.pt")):
        return None
    return max(max(tensor_differences(stage / n, source / n).values()) for n in names)


def compare_stages(run: Path, sources: list[Path], remove: bool) -> list[str]:
    """One line a stage folder of `run`: a copy (max |Δw| 0), a differing folder, or new; the
    copies are removed (with `remove`) only once every folder has been compared."""
    lines, copies = [], []
    for name, source in stage_sources(run, sources).items():
        delta = None if source is None else folder_difference(run / name, source)
        if source is None:
            lines.append(f"{name}: new (no source has it); kept")
        elif delta is None:
            lines.append(f"{name}: other checkpoints than {source}; kept")
        elif delta == 0.0:
            copies.append(run / name)
            verdict = "removed" if remove else "a copy"
            lines.append(f"{name}: max |Δw| 0 against {source} (every actor tensor); {verdict}")
        else:
            lines.append(f"{name}: max |Δw| {delta:.3g} against {source}; kept")
    for folder in copies if remove else []:
        shutil.rmtree(folder)
    return lines


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", type=Path, nargs="+", help="A.pt B.pt, or RUN SOURCE...")
    parser.add_argument("--stages", action="store_true", help="RUN's stage folders vs SOURCEs'")
    parser.add_argument("--remove-copies", action="store_true", help="with --stages")
    args = parser.parse_args(argv)
    if args.remove_copies and not args.stages:
        parser.error("--remove-copies goes with --stages")
    if not args.stages and len(args.paths) != 2:
        parser.error("give two checkpoints (or --stages RUN SOURCE...)")
    if args.stages and len(args.paths) < 2:
        parser.error("--stages needs RUN and at least one SOURCE")
    wanted = Path.is_dir if args.stages else Path.is_file
    missing = [str(p) for p in args.paths if not wanted(p)]
    if missing:
        parser.error(
            f"no such {'run folder' if args.stages else 'checkpoint'}: {', '.join(missing)}"
        )
    try:
        if args.stages:
            print("\n".join(compare_stages(args.paths[0], args.paths[1:], args.remove_copies)))
        else:
            print(summary(tensor_differences(*args.paths)))
    except RealIkeaError as err:
        print(f"weight_difference.py: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
