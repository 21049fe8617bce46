"""Videos of each run's evaluation and the report's section showing their frames."""

from __future__ import annotations

from pathlib import Path

from realikea.eval.protocol import outcome_table
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.video import record_draw
from realikea.runs.records import command_overrides

from .tables import relative


def record_videos(runs: list[dict], episodes: int) -> None:
    """Each run's evaluation (`video_overrides`) with the first of its recorded episodes of each
    strategy label as MP4 and frame strip in RUN/videos/. A run whose videos/ already holds
    strips is skipped (delete the folder to record it again), so a stopped recording resumes."""
    for run in runs:
        if run["strips"]:
            continue
        stem = run["dir"] / "videos" / "eval.mp4"
        for old in stem.parent.glob("eval_*"):  # labels of an earlier recording
            old.unlink()
        print(f"recording {run['dir']}")
        evaluate_and_record(video_overrides(run, episodes), stem)
        run["strips"] = sorted(stem.parent.glob("*.png"))


def video_overrides(run: dict, episodes: int) -> list[str]:
    """The overrides of the run's evaluation under its training resistance (eval.json's command)
    with `episodes` episodes, its envs in this process and the checkpoint kept in the run's
    directory (the command names where it was trained)."""
    modes = run["eval"]["modes"]
    entry = modes.get(run["resistance"]) or next(iter(modes.values()))
    checkpoint = (run["dir"] / run["eval"]["checkpoint"]).resolve()
    replaced = ("episodes=", "policy.path=")
    kept = [o for o in command_overrides(entry["command"]) if not o.startswith(replaced)]
    return [*kept, f"policy.path={checkpoint}", f"episodes={episodes}", "env.num_workers=0"]


def evaluate_and_record(overrides: list[str], stem: Path) -> dict[str, Path]:
    """What `realikea eval OVERRIDES video=true video_path=STEM` does: the evaluation's outcome
    table, then the recorded episodes (`record_draw`); returns key -> MP4."""
    cfg, policy = eval_setup(overrides)
    print(outcome_table(evaluate(cfg, policy)))
    return record_draw(cfg, policy, stem)


def typical_strategy(run: dict) -> str | None:
    """The most frequent strategy label of the run's evaluation under its training resistance."""
    entry = run["eval"]["modes"].get(run["resistance"]) or {}
    strategies = entry.get("strategies") or {}
    return max(strategies, key=strategies.get) if strategies else None


def frame_lines(runs: list[dict], out: Path) -> list[str]:
    """Per run, the four-frame strip of its typical strategy inline and its other strips named."""
    lines = [
        "## Frames of the typical strategy per run",
        "",
        "Four frames (the scene above a close-up of the handle) of one recorded evaluation "
        "episode under the run's training resistance with the run's most frequent strategy "
        "label: the first success with that label, else its first episode. Strips of the other "
        "labels seen in the recorded episodes are linked. The MP4 beside each strip is "
        "git-ignored and written again by `--record-videos`.",
        "",
    ]
    recorded = [run for run in runs if run["strips"]]
    for run in recorded:
        cell = f"{run['variant']} / {run['category']} / trained on {run['resistance']}"
        cell += f" / s{run['seed']}"
        typical = typical_strategy(run)
        by_label = {s.stem.removeprefix("eval_").rsplit("_", 1)[0]: s for s in run["strips"]}
        shown = by_label.get(typical)
        others = [f"[{label}]({relative(s, out)})" for label, s in by_label.items() if s != shown]
        lines.append(f"### {cell}")
        lines.append("")
        if shown is not None:
            video = relative(shown.with_suffix(".mp4"), out)
            outcome = shown.stem.rsplit("_", 1)[-1]
            lines += [f"Typical: `{typical}`, an episode ending in {outcome} ([MP4]({video})).", ""]
            lines += [f"![{cell} {typical}]({relative(shown, out)})", ""]
        else:
            lines += [f"Typical: `{typical}`, not among the recorded episodes.", ""]
        if others:
            lines += ["Other labels: " + ", ".join(others) + ".", ""]
    if not recorded:
        lines.append(
            "None recorded: `python experiments/fidelity_ablation/report.py --record-videos` "
            "writes one MP4 and strip per strategy label into each RUN/videos/."
        )
    return lines
