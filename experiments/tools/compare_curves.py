"""Training success of several runs on one axis (50-iteration running mean of the per-iteration
fraction), for comparing recipes or collision sources at a glance; the learning curve of each
run stays in its own folder (plot_learning_curve.py).

python experiments/tools/compare_curves.py --out FILE [--switch IT] [--title T] LABEL=RUN_DIR ...
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from realikea.files import atomic_path  # noqa: E402
from realikea.training.metrics import read_metrics, running_mean  # noqa: E402

WINDOW = 50


def labelled_run(text: str) -> tuple[str, Path]:
    """LABEL=RUN_DIR, the folder holding a metrics.csv (split at the last '=')."""
    label, sep, folder = text.rpartition("=")
    if not sep or not label or not (Path(folder) / "metrics.csv").is_file():
        raise argparse.ArgumentTypeError(f"{text!r}: expected LABEL=RUN_DIR, RUN_DIR/metrics.csv")
    return label, Path(folder)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=labelled_run, metavar="LABEL=RUN_DIR")
    parser.add_argument("--out", type=Path, required=True, help="PNG to write")
    parser.add_argument("--switch", type=int, help="iteration of the switch to randomized poses")
    parser.add_argument("--title", default="training success")
    args = parser.parse_args()
    fig, ax = plt.subplots(figsize=(8, 4))
    for label, folder in args.runs:
        its, values = read_metrics(folder).get("/episode/success", ([], []))
        ax.plot(its, running_mean(values, WINDOW), label=label)
    if args.switch is not None:
        ax.axvline(args.switch, color="grey", linestyle="--", label="randomized poses")
    ax.set(title=f"{args.title} ({WINDOW}-iteration mean)", xlabel="iteration", ylim=(0, 1))
    ax.legend()
    fig.tight_layout()
    with atomic_path(args.out) as tmp:
        fig.savefig(tmp, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
