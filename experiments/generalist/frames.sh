#!/usr/bin/env bash
# Frames of a generalist checkpoint on held-out parts: a PNG strip (four frames, the scene above
# a close-up of the handle) and an MP4 (git-ignored) per strategy label of the first episodes,
# one folder per kind x category, under experiments/generalist/<name>/frames/.
# Usage: bash experiments/generalist/frames.sh NAME [CHECKPOINT]   (NAME: coacd or hull)
set -euo pipefail
cd "$(dirname "$0")/../.."
NAME="$1"
CKPT="${2:-$(ls experiments/generalist/"$NAME"/model_*.pt | sort -V | tail -1)}"
mkdir -p "experiments/generalist/$NAME/frames"
for kind in door flap drawer; do
  for category in two_point knob finger_pull; do
    MUJOCO_GL="${MUJOCO_GL:-osmesa}" realikea eval policy=checkpoint policy.path="$CKPT" \
      asset="$category" asset.kind="$kind" resistance=high dr=randomized env.seed=1000 \
      episodes=6 video=true video_episodes=6 \
      video_path="experiments/generalist/$NAME/frames/${kind}_${category}" | tail -1
  done
done
