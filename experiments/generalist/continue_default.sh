#!/usr/bin/env bash
# The default generalist's seeds 0 and 2 continued from iteration 1,499 for 1,000 more
# iterations (the resume repeats 1,499, so the last checkpoint is model_2498), side by side,
# one env worker each, on the single-task agent they trained with (agent=ppo); then kept in
# results/default/s<seed>_2500/ and evaluated as the default (test parts, kitchen, smooth and
# high). Needs the full checkpoints of `train_gated.py` in outputs/generalist/default_s<seed>/.
# A stopped run continues with the same command and train.resume= its own last checkpoint in
# outputs/generalist/default_s<seed>_cont/.
# Usage: bash experiments/generalist/continue_default.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
HERE=experiments/generalist
for seed in 0 2; do
  python train.py logger=none pipeline=none agent=ppo env.seed="$seed" env.num_workers=1 agent.save_interval=25 \
    train.resume="outputs/generalist/default_s$seed/model_1499.pt" agent.max_iterations=1000 \
    hydra.run.dir="outputs/generalist/default_s${seed}_cont" > "outputs/generalist/default_s${seed}_cont.log" 2>&1 &
done
wait
for seed in 0 2; do
  python "$HERE/keep.py" "outputs/generalist/default_s${seed}_cont" "default/s${seed}_2500" \
    --continues "outputs/generalist/default_s$seed"
done
for seed in 0 2; do
  python "$HERE/evaluate.py" "$HERE/results/default/s${seed}_2500/model_2498.pt" \
    "default/s${seed}_2500" --modes smooth high &
done
wait
