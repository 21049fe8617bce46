#!/usr/bin/env bash
# Frames of Table 2's friction-based baselines in the kitchen on test parts, high resistance,
# franka_hand / elliptic: one episode per strategy label (its first success if any) as an MP4
# (git-ignored) and a four-frame PNG strip in experiments/table2/results/frames/.
# Usage: bash experiments/table2/frames.sh [EPISODES]   (default 3 recorded episodes a cell)
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-3}"
for cell in "heuristic_pull knob door" "grasp_sampler finger_pull drawer"; do
  read -r policy category kind <<< "$cell"
  realikea eval policy="$policy" asset="$category" asset.kind="$kind" asset.split=test \
    resistance=high dr=randomized scene=kitchen gripper=franka_hand contact=elliptic \
    episodes=2 env.num_workers=0 video=true video_episodes="$EPISODES" \
    video_path="experiments/table2/results/frames/kitchen_${policy}_${category}_${kind}.mp4" | grep '^video'
done
