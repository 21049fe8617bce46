#!/usr/bin/env bash
# The generalist, end to end: train with the defaults (CoACD) and the same recipe on the hull,
# keep the slim checkpoints and curves, evaluate both on the held-out parts over
# kind x category x resistance mode, write table.md, and record frames.
# Session 6 ran the two trainings side by side on the 2 cores (each ~1 h 35 min beside other
# jobs); a stopped training continues with `python train.py train.resume=RUN/model_<it>.pt ...`
# and the grid evaluation skips the cells already in <name>/cells.jsonl.
# Usage: bash experiments/generalist/run.sh [EPISODES]   (default 50 episodes a cell)
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
HERE=experiments/generalist
python train.py logger=none hydra.run.dir=outputs/generalist/coacd_s0 &
python train.py logger=none collision=hull hydra.run.dir=outputs/generalist/hull_s0 &
wait
for name in coacd hull; do
  python "$HERE/keep.py" "outputs/generalist/${name}_s0" "$name"
  python "$HERE/evaluate.py" "$(ls "$HERE/$name"/model_*.pt | sort -V | tail -1)" "$name" \
    --episodes "$EPISODES"
done
python "$HERE/report.py"
bash "$HERE/frames.sh" coacd "door flap" 4
