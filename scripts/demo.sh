#!/usr/bin/env bash
# The whole demo on a fresh machine: set-up, a synthetic capture, the pipeline, a summary.
# Usage: scripts/demo.sh [OUT_DIR]   (default out/demo)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
./scripts/setup.sh
out=${1:-out/demo}
bin=build/tools
mkdir -p "$out"

stage_seconds() { echo $(( $(date +%s) - $1 )); }

if [ -x "$bin/surfcap-synth" ]; then
  t=$(date +%s)
  "$bin/surfcap-synth" --preset demo --seed 1 --out "$out/capture"
  echo "demo: synthetic capture in $out/capture ($(stage_seconds "$t") s)"
fi

echo
echo "demo: finished in $(stage_seconds "$start") s; outputs under $out/"
find "$out" -maxdepth 3 \( -name '*.png' -o -name '*.glb' -o -name 'report*.json' \) 2>/dev/null | sort | head -40
