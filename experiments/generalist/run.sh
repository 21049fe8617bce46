#!/usr/bin/env bash
# The generalist, end to end: train with the defaults (CoACD) and the same recipe on the hull,
# keep the slim checkpoints and curves, evaluate both on the held-out parts over
# kind x category x resistance mode, write table.md, and record frames.
# The two trainings ran side by side on the 2 cores (each ~1 h 35 min beside other
# jobs); a stopped training continues with `python train.py train.resume=RUN/model_<it>.pt ...`
# and the grid evaluation skips the cells already in <name>/cells.jsonl.
# Usage: bash experiments/generalist/run.sh [EPISODES]   (default 50 episodes a cell)
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
HERE=experiments/generalist
OUT=$HERE/results
# the recipe these runs were trained with: one run of the single-task agent, the appendix reward
# (latched), every env in lockstep
APPENDIX="pipeline=none agent=ppo task/reward=appendix agent.init_at_random_ep_len=false"
python train.py logger=none $APPENDIX hydra.run.dir=outputs/generalist/coacd_s0 &
python train.py logger=none $APPENDIX collision=hull hydra.run.dir=outputs/generalist/hull_s0 &
wait
for name in coacd hull; do
  python "$HERE/keep.py" "outputs/generalist/${name}_s0" "$name"
  python "$HERE/evaluate.py" "$(ls "$OUT/$name"/model_*.pt | sort -V | tail -1)" "$name" \
    --episodes "$EPISODES"
done
# the CoACD run continued for 1,000 more iterations (63 min beside two other runs)
python train.py logger=none $APPENDIX train.resume=outputs/generalist/coacd_s0/model_1499.pt \
  agent.max_iterations=1000 hydra.run.dir=outputs/generalist/coacd_s0_cont
python "$HERE/keep.py" outputs/generalist/coacd_s0_cont coacd_2500 --continues outputs/generalist/coacd_s0
python "$HERE/evaluate.py" "$OUT/coacd_2500/model_2498.pt" coacd_2500 --episodes "$EPISODES"
# the same recipe with the appendix's w_open2 = 0, both sources
python train.py logger=none $APPENDIX collision=hull task.reward.w_open2=0 \
  hydra.run.dir=outputs/generalist/hull_open2_0_s0 &
python train.py logger=none $APPENDIX task.reward.w_open2=0 hydra.run.dir=outputs/generalist/coacd_open2_0_s0 &
wait
python "$HERE/keep.py" outputs/generalist/hull_open2_0_s0 hull_open2_0
python "$HERE/keep.py" outputs/generalist/coacd_open2_0_s0 coacd_open2_0
for name in hull_open2_0 coacd_open2_0; do
  python "$HERE/evaluate.py" "$OUT/$name/model_1499.pt" "$name" --episodes "$EPISODES"
done
python experiments/tools/compare_curves.py --switch 900 --out "$OUT/open_jaw_bonus.png" \
  --title "generalist, seed 0: training success" \
  "CoACD, w_open2 = 2=$OUT/coacd" "hull, w_open2 = 2=$OUT/hull" \
  "CoACD, w_open2 = 0=$OUT/coacd_open2_0" "hull, w_open2 = 0=$OUT/hull_open2_0"
python "$HERE/report.py"
bash "$HERE/frames.sh" coacd "door flap" 4
