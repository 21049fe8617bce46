#!/usr/bin/env bash
# Make the environment that reads the recorded LeRobot datasets back with lerobot's own
# LeRobotDataset (experiments/lerobot_sample/readback.sh runs it): a venv of its own, because the
# project pins torch 2.13.0 (the CPU build) and lerobot imports torchvision, whose registry wheels
# are built against the registry's torch. So: torch 2.14.1 and torchvision 0.29.1 as the registry
# ships them (CUDA 13.0 builds that load and run on a CPU-only machine; the nvidia-* CUDA wheels
# and triton come with them, 4.1 GB of the venv's 5.9 GB), lerobot 0.4.4 with --no-deps (it declares torch<2.11 and torchvision<0.26 and a
# robot stack: draccus, rerun-sdk, wandb, opencv, pynput, pyserial, diffusers, ...), and of its
# Requires-Dist only what `lerobot.datasets.lerobot_dataset` imports when it loads and reads a
# dataset: datasets, huggingface-hub, accelerate (lerobot.utils.utils), av (video_utils, imported
# even for a dataset without video), packaging; plus numpy, pandas, pyarrow, pillow and fsspec,
# which lerobot imports without declaring them. torchcodec (video decoding, imported lazily) is
# left out: the datasets have no video. realikea is not installed here: the project's own Python
# writes the datasets, this one only reads them (tests/test_lerobot_readback.py imports no
# realikea). Pins: lerobot's ranges, the versions this read back with on 2026-11-28.
# Usage: bash experiments/lerobot_sample/make_env.sh [VENV]   (default: .venv-lerobot)
set -euo pipefail
cd "$(dirname "$0")/../.."
VENV=${1:-.venv-lerobot}
SUDO=$([ "$(id -u)" -eq 0 ] && echo "" || echo "sudo")
if ! python3 -c "import ensurepip" 2>/dev/null; then
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq python3-venv >/dev/null
fi
python3 -m venv "$VENV"
PIP=("$VENV/bin/python" -m pip --disable-pip-version-check)
"${PIP[@]}" install -q torch==2.14.1 torchvision==0.29.1 \
  datasets==4.8.5 huggingface-hub==0.35.3 accelerate==1.15.0 av==15.1.0 packaging==25.0 \
  numpy==2.4.6 pandas==3.1.1 pyarrow==26.0.1 pillow==13.0.0 fsspec==2026.2.0 \
  pytest==9.2.0
"${PIP[@]}" install -q --no-deps lerobot==0.4.4  # last: pip then checks none of its pins
"$VENV/bin/python" - <<'PY'
from importlib.metadata import version

import torch
import torchvision
from lerobot.datasets.lerobot_dataset import LeRobotDataset  # noqa: F401

print(f"torch {torch.__version__} (CUDA {torch.version.cuda}, available: {torch.cuda.is_available()})")
print(f"torchvision {torchvision.__version__}, lerobot {version('lerobot')}")
PY
du -sh "$VENV"
