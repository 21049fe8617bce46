"""Which text files of the repository cite a committed checkpoint, so one nothing cites can go.

A checkpoint `<study>/results/.../<run>/model_<N>.pt` is cited by a text file (Markdown, code,
shell, JSON, YAML, CSV; never a run's Hydra record or its `metrics.csv`) that

1. names it by path, from the repository's root or from its study's folder, or by a pattern
   that matches it, where `*`, `<name>` and `${name}` stand for any text
   (`results/runs/${collision}_high_s${seed}/model_499.pt`);
2. lies in its own run folder (an `eval.json`, a sweep, frames' index) and names its file
   (`"checkpoint": "model_899.pt"`) or its iteration (a sweep's `"iteration": 899`);
3. names, on one line, both its run folder and its file: a results table's row
   (`| gated_hull_knob_high_s0 | model_250.pt | ...`).
"""

from __future__ import annotations

import os
import re
from fnmatch import fnmatchcase
from pathlib import Path

TEXT_SUFFIXES = (".md", ".py", ".sh", ".json", ".jsonl", ".yaml", ".yml", ".csv", ".txt", ".toml")
SKIPPED_DIRS = {".git", ".hydra", ".venv", ".cache", "outputs", "__pycache__", "node_modules"}
SKIPPED_FILES = {"metrics.csv"}  # training logs: numbers, never a citation

# a path-like token ending in .pt; <...> and ${...} placeholders are kept whole
PT_TOKEN = re.compile(r"(?:[\w.\-/*]|<[^<>\s]*>|\$\{[^{}\s]*\})+\.pt\b")
PLACEHOLDER = re.compile(r"<[^<>\s]*>|\$\{[^{}\s]*\}")


def text_files(root: Path) -> list[Path]:
    """The repository's text files that may cite a checkpoint, outside generated folders."""
    found = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d not in SKIPPED_DIRS and not d.endswith(".egg-info")]
        found += [
            Path(folder, f) for f in files if f.endswith(TEXT_SUFFIXES) and f not in SKIPPED_FILES
        ]
    return sorted(found)


def path_patterns(lines: list[str]) -> set[str]:
    """Every `.pt` path or pattern the lines name, placeholders turned into `*`."""
    return {PLACEHOLDER.sub("*", t) for line in lines for t in PT_TOKEN.findall(line)}


def names_path(pattern: str, checkpoint: str, within_study: str) -> bool:
    """Whether a path or pattern names the checkpoint (repository-relative `checkpoint`, and
    `within_study` relative to its study's folder); a bare file name names no checkpoint."""
    if "/" not in pattern:
        return False
    pattern = pattern.removeprefix("./")
    return fnmatchcase(checkpoint, pattern) or fnmatchcase(within_study, pattern)


def names_in_own_run(text: str, checkpoint: Path) -> bool:
    """Whether a result in the checkpoint's own run folder names its file or its iteration."""
    if checkpoint.name in text:
        return True
    iteration = checkpoint.stem.removeprefix("model_")
    return re.search(rf'"iteration":\s*{iteration}\b', text) is not None


def names_run(line: str, checkpoint: Path) -> bool:
    """Whether a line names the checkpoint's run folder as a whole word."""
    run = re.escape(checkpoint.parent.name)
    return re.search(rf"(?<![\w\-]){run}(?![\w\-])", line) is not None


def citations(root: Path, checkpoints: list[Path]) -> dict[Path, list[str]]:
    """For each checkpoint (a path under `root/<study>/...`), the repository-relative text
    files that cite it (the rules above), sorted."""
    texts = {
        p.relative_to(root).as_posix(): p.read_text(errors="replace") for p in text_files(root)
    }
    lines = {n: [line for line in t.splitlines() if ".pt" in line] for n, t in texts.items()}
    patterns = {n: path_patterns(found) for n, found in lines.items() if found}
    by_file_name: dict[str, list[tuple[str, str]]] = {}  # model_N.pt -> (text, line)
    for name, found in lines.items():
        for line in found:
            for file_name in set(re.findall(r"model_\d+\.pt", line)):
                by_file_name.setdefault(file_name, []).append((name, line))
    cited: dict[Path, list[str]] = {}
    for checkpoint in checkpoints:
        relative = checkpoint.relative_to(root).as_posix()
        study = "/".join(relative.split("/")[:2])  # experiments/<study>
        within_study = relative.removeprefix(study + "/")
        run = relative.rsplit("/", 1)[0] + "/"
        by = {
            n
            for n, found in patterns.items()
            if any(names_path(p, relative, within_study) for p in found)
        }
        by |= {n for n, t in texts.items() if n.startswith(run) and names_in_own_run(t, checkpoint)}
        by |= {
            n for n, line in by_file_name.get(checkpoint.name, []) if names_run(line, checkpoint)
        }
        cited[checkpoint] = sorted(by)
    return cited
