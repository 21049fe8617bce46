#!/usr/bin/env bash
# Cold and cached build of the whole library (1,079 configurations, both collision sources)
# into a fresh cache and output folder; prints both summaries and the wall times.
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for run in cold cached; do
  SECONDS=0
  REALIKEA_CACHE="$work/cache" realikea assets build --all --out "$work/library" 2>/dev/null
  echo "$run: ${SECONDS} s wall (process start to exit)"
done
echo "library folder: $(du -sh "$work/library" | cut -f1) (meshes hard-linked from the cache)"
