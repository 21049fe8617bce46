"""Fidelity-ablation report: every finished run (a directory holding `.hydra/config.yaml`,
`eval.json` and `metrics.csv`) under the given roots, aggregated into report.md and plots.

python experiments/fidelity_ablation/report.py [ROOT ...] [--out DIR] [--record-videos]
    [--phase-maps MAP ...]

ROOT defaults to outputs/fidelity_ablation (all sweeps in it); runs are found at any depth.
Cells are (collision source, training resistance, category) per gripper/contact preset;
seeds of a cell are averaged. Writes DIR/report.md (default experiments/fidelity_ablation/results),
success.png, outcomes.png, strategies.png and learning_curves.png. `--record-videos` does
what `realikea eval ... video=true episodes=N` does once per run not yet recorded (under its
training resistance, N = --video-episodes, 8), which writes the first MP4 (and a PNG strip of four
frames) of each strategy label into RUN/videos/; the report shows every RUN/videos/*.png strip it
finds and names the MP4 beside it. Each `--phase-maps` directory (written by phase_map.py) adds
its heat maps and CoACD − hull differences. The committed report:

    python experiments/fidelity_ablation/report.py experiments/fidelity_ablation/results/grid \
        --phase-maps experiments/fidelity_ablation/results/phase_map{,_paper,_paper_s1,_paper_s2}
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from fidelity_report.report import report
from fidelity_report.videos import record_videos

from realikea.errors import RealIkeaError
from realikea.files import repo_path
from realikea.runs.records import find_runs

DEFAULT_OUT = "experiments/fidelity_ablation/results"  # the committed report


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("roots", nargs="*", type=Path, default=[Path("outputs/fidelity_ablation")])
    parser.add_argument("--out", type=Path, default=repo_path(DEFAULT_OUT), help="report directory")
    parser.add_argument("--record-videos", action="store_true")
    parser.add_argument(
        "--video-episodes", type=int, default=8, help="episodes per run for --record-videos"
    )
    parser.add_argument(
        "--phase-maps", nargs="*", type=Path, default=[], help="phase_map.py output directories"
    )
    args = parser.parse_args(argv)
    try:
        if args.record_videos:
            record_videos(find_runs(args.roots), args.video_episodes)
        path = report(args.roots, args.out, args.phase_maps)
    except RealIkeaError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    print(f"report: {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
