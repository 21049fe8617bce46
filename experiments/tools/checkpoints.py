"""The committed checkpoints of every study: counts and sizes, the ones nothing cites
(realikea.runs.citations), and each study's manifest (realikea.runs.manifest).

    python experiments/tools/checkpoints.py            # per study; every uncited checkpoint
    python experiments/tools/checkpoints.py --write    # write <study>/results/checkpoints.csv
    python experiments/tools/checkpoints.py --prune    # delete the uncited ones (then git rm)
"""

from __future__ import annotations

import argparse

from realikea.files import WORKSPACE
from realikea.markdown import table
from realikea.runs.citations import citations
from realikea.runs.manifest import study_checkpoints, write_manifest

EXPERIMENTS = WORKSPACE / "experiments"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    action = parser.add_mutually_exclusive_group()
    action.add_argument("--write", action="store_true", help="write each study's manifest")
    action.add_argument("--prune", action="store_true", help="delete uncited checkpoints")
    args = parser.parse_args()
    found = {s: paths for s in sorted(EXPERIMENTS.iterdir()) if (paths := study_checkpoints(s))}
    cited = citations(WORKSPACE, [p for paths in found.values() for p in paths])
    uncited = [p for p, by in cited.items() if not by]
    rows = [
        [study.name, str(len(paths)), f"{sum(p.stat().st_size for p in paths) / 1e6:.1f}",
         str(sum(p in uncited for p in paths))]
        for study, paths in found.items()
    ]  # fmt: skip
    print("\n".join(table(["study", "checkpoints", "MB", "uncited"], "lrrr", rows)))
    for path in uncited:
        print(f"uncited: {path.relative_to(WORKSPACE)}")
    if args.prune:
        for path in uncited:
            path.unlink()
        print(f"deleted {len(uncited)} uncited checkpoints")
    if args.write:
        for study in found:
            print(f"wrote {write_manifest(study).relative_to(WORKSPACE)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
