#!/usr/bin/env bash
# Install everything Real-IKEA needs on a fresh Debian machine: Mesa's OSMesa for offscreen
# MuJoCo rendering on the CPU, then this package with its Python dependencies (editable).
set -euo pipefail
cd "$(dirname "$0")"
if ! ldconfig -p | grep -q libOSMesa; then
  SUDO=$([ "$(id -u)" -eq 0 ] && echo "" || echo "sudo")
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq libosmesa6 >/dev/null
fi
python3 -m pip install -q --disable-pip-version-check -e '.[dev]'
