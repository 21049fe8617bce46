#!/usr/bin/env bash
# Record the sample's eval as a LeRobot dataset and read it back with lerobot's own
# LeRobotDataset, in one command:
# 1. the project's Python (. ./env.sh) runs the README's eval with record= into a temporary folder
#    (OVERRIDEs, e.g. paths.library=DIR, are appended to it) and compares its data file with the
#    committed sample's;
# 2. the read-back environment (make_env.sh: torch 2.14.1, torchvision 0.29.1, lerobot 0.4.4; made
#    first when LEROBOT_VENV, default .venv-lerobot, has none) runs tests/test_lerobot_readback.py
#    on that export and on the committed samples (no stub: the test checks that the installed
#    lerobot and torchvision are the ones loaded, torchvision's compiled ops included), then
#    prints what LeRobotDataset read;
# 3. that output, with the command, the versions and the date, goes to results/readback.md.
# Usage: bash experiments/lerobot_sample/readback.sh [OVERRIDE ...]
set -euo pipefail
cd "$(dirname "$0")/../.."
VENV=${LEROBOT_VENV:-.venv-lerobot}
SAMPLE=experiments/lerobot_sample/results
if [ ! -x "$VENV/bin/python" ]; then
  bash experiments/lerobot_sample/make_env.sh "$VENV"
fi
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
EXPORT=$OUT/heuristic_pull
EVAL=(realikea eval policy=heuristic_pull asset=all resistance=high dr=randomized episodes=4
  env.num_workers=0 task.episode_seconds=8 "record=$EXPORT" "$@")

readback() {
  echo "realikea at commit $(git rev-parse --short HEAD), with $(git status --porcelain -- realikea |
    wc -l) uncommitted file(s) under realikea/"
  echo "\$ ${EVAL[*]}   # the project's Python"
  (. ./env.sh && "${EVAL[@]}")
  if cmp -s "$EXPORT/data/chunk-000/file-000.parquet" "$SAMPLE/heuristic_pull/data/chunk-000/file-000.parquet"; then
    echo "its data file: identical to $SAMPLE/heuristic_pull's"
  else
    echo "its data file: differs from $SAMPLE/heuristic_pull's"
  fi
  echo
  echo "\$ REALIKEA_LEROBOT_EXPORT=$EXPORT $VENV/bin/python -m pytest -q -p no:cacheprovider --noconftest tests/test_lerobot_readback.py"
  REALIKEA_LEROBOT_EXPORT=$EXPORT "$VENV/bin/python" -m pytest -q -p no:cacheprovider \
    --noconftest tests/test_lerobot_readback.py | tee "$OUT/pytest.log"
  if grep -q skipped "$OUT/pytest.log"; then
    echo "a read-back test was skipped" >&2
    exit 1
  fi
  echo
  echo "\$ $VENV/bin/python   # LeRobotDataset(...) on each dataset"
  "$VENV/bin/python" - "$EXPORT" "$SAMPLE"/*/ <<'PY'
import platform
import sys
from importlib.metadata import version
from pathlib import Path

import torch
from lerobot.datasets.lerobot_dataset import LeRobotDataset

print(
    f"Python {platform.python_version()}; torch {torch.__version__} (CUDA available: "
    f"{torch.cuda.is_available()}), torchvision {version('torchvision')}, "
    f"lerobot {version('lerobot')}, datasets {version('datasets')}, pandas {version('pandas')}, "
    f"pyarrow {version('pyarrow')}"
)
for root in map(Path, sys.argv[1:]):
    ds = LeRobotDataset(f"realikea/{root.name}", root=root)
    print(
        f"{root}: {len(ds)} frames, {ds.num_episodes} episodes, fps {ds.fps}, "
        f"{len(ds.meta.tasks)} tasks, {len(ds.features)} features"
    )
    episodes = ds.meta.episodes
    for k in range(ds.num_episodes):
        print(
            f"  episode {episodes['episode_index'][k]}: {episodes['config_id'][k]}, "
            f"{episodes['length'][k]} frames, {episodes['outcome'][k]}, "
            f"{episodes['strategy'][k]}, {episodes['termination'][k]}"
        )
PY
}

START=$(date +%s)
readback | tee "$OUT/output.txt"
{
  echo "# LeRobot read-back"
  echo
  echo "Written by \`bash experiments/lerobot_sample/readback.sh${*:+ $*}\` on $(date -u +%Y-%m-%d)"
  echo "(UTC), in $(($(date +%s) - START)) s; its output:"
  echo
  echo '```'
  cat "$OUT/output.txt"
  echo '```'
} >"$SAMPLE/readback.md"
echo "written: $SAMPLE/readback.md"
