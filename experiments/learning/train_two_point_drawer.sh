#!/usr/bin/env bash
# The learning check: PPO on two-point-handle drawers, smooth resistance, CoACD
# collision, fixed poses; then 50 evaluation episodes of the final checkpoint and the curve.
set -euo pipefail
run=${1:-outputs/runs/two_point_drawer_smooth_coacd}
python train.py asset=two_point asset.kind=drawer resistance=smooth collision=coacd dr=fixed \
  logger=none env.num_envs=32 agent.num_steps_per_env=48 task/reward=appendix \
  task.reward.w_open2=0.0 agent.init_at_random_ep_len=false \
  agent.max_iterations=${ITERATIONS:-700} hydra.run.dir="$run"
last=$(ls "$run"/model_*.pt | sort -V | tail -1)
python experiments/tools/plot_learning_curve.py "$run"
realikea eval policy=checkpoint policy.path="$last" asset=two_point asset.kind=drawer \
  resistance=smooth collision=coacd dr=fixed episodes=50 env.seed=1000 \
  env.num_envs=32
