#!/usr/bin/env bash
# Frames of a generalist checkpoint on held-out parts: a PNG strip (four frames, the scene above
# a close-up of the handle) and an MP4 (git-ignored) per strategy label of the first episodes,
# named <kind>_<category>_<label>_<outcome> (BY=strategy), or of the first success and the first
# failure, <kind>_<category>_<outcome>_<label> (BY=outcome), under experiments/generalist/results/<name>/frames/.
# Usage: bash experiments/generalist/frames.sh NAME [KINDS] [EPISODES] [BY] [OVERRIDES...]
#   NAME: a folder holding the checkpoint, e.g. coacd or default/s0 (its last checkpoint);
#   KINDS default "door flap"; EPISODES default 4; BY default strategy; OVERRIDES go to every
#   `realikea eval` (e.g. collision=hull: a hull-trained policy on its own geometry)
set -euo pipefail
cd "$(dirname "$0")/../.."
NAME="$1"
KINDS="${2:-door flap}"
EPISODES="${3:-4}"
BY="${4:-strategy}"
shift $(( $# < 4 ? $# : 4 ))
CKPT="$(ls experiments/generalist/results/"$NAME"/model_*.pt | sort -V | tail -1)"
mkdir -p "experiments/generalist/results/$NAME/frames"
for kind in $KINDS; do
  for category in two_point knob finger_pull; do
    MUJOCO_GL="${MUJOCO_GL:-osmesa}" realikea eval policy=checkpoint policy.path="$CKPT" \
      asset="$category" asset.kind="$kind" resistance=high dr=randomized env.seed=1000 \
      episodes="$EPISODES" video=true video_episodes="$EPISODES" video_by="$BY" \
      video_path="experiments/generalist/results/$NAME/frames/${kind}_${category}" "$@" | tail -1
  done
done
