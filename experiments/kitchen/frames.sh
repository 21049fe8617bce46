#!/usr/bin/env bash
# Frames of hook_oracle on the finger pulls and the knobs (franka_hand, elliptic, high
# resistance, test parts, kitchen): one episode per strategy label, its first success if any, as an
# MP4 (git-ignored) and a four-frame PNG strip in experiments/kitchen/results/frames/.
# Usage: bash experiments/kitchen/frames.sh [EPISODES]   (default 4 recorded episodes a cell)
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-4}"
for cell in "finger_pull drawer" "finger_pull flap" "knob drawer" "knob door"; do
  read -r category kind <<< "$cell"
  realikea eval policy=hook_oracle asset="$category" asset.kind="$kind" asset.split=test \
    resistance=high dr=randomized scene=kitchen gripper=franka_hand contact=elliptic \
    episodes=2 env.num_workers=0 video=true video_episodes="$EPISODES" \
    video_path="experiments/kitchen/results/frames/hook_oracle_${category}_${kind}.mp4" | grep '^video'
done
