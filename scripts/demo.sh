#!/usr/bin/env bash
# The whole demo on a fresh machine: set-up, a synthetic capture (surfcap-synth --preset demo),
# the pipeline (pipelines/character.mk), then a summary: alignment error, blend errors,
# transition costs, asset size, wall time per stage, and where the character and previews are.
# Usage: scripts/demo.sh [OUT_DIR]   (default out/demo)
# Environment:
#   DATABASE=aligned|truth  which database the stages after alignment read (default aligned: the
#                           output of surfcap-align, 0.496 % RMS / 1.075 % worst frame of the
#                           height on this capture, docs/align.md; truth: the capture's ground
#                           truth, to compare the later stages without the alignment's error)
#   ROOT (default walk:0)   the template frame: a stride of the walk (docs/align.md)
#   JOBS (default nproc)    parallel make jobs; THREADS (default 2) threads per step
#   SUBMIT                  command prefix of the heavy steps (e.g. "srun -c 2", docs/pipelines.md)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
out=${1:-out/demo}
database=${DATABASE:-aligned}
jobs=${JOBS:-$(nproc)}
threads=${THREADS:-2}

# make and python3 drive the pipeline; the rest is scripts/setup.sh's.
if ! command -v make >/dev/null || ! command -v python3 >/dev/null; then
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends make python3
fi
tools=(surfcap-synth surfcap-align surfcap-learn surfcap-precompute surfcap-export surfcap-play)
./scripts/setup.sh "${tools[@]/#/--target=}"
setup_s=$(( $(date +%s) - start ))

rm -rf "$out"
mkdir -p "$out"
t=$(date +%s)
echo "demo: surfcap-synth --preset demo"
build/tools/surfcap-synth --preset demo --seed 1 --out "$out/capture" --log-level warn
synth_s=$(( $(date +%s) - t ))

echo "demo: pipeline (make -j $jobs, $threads threads per step, later stages read the $database database)"
t=$(date +%s)
make --no-print-directory -f pipelines/character.mk -j "$jobs" CAPTURE="$out/capture" \
  GRAPH=configs/graphs/demo.json OUT="$out" DATABASE="$database" THREADS="$threads" \
  ${SUBMIT:+SUBMIT="$SUBMIT"} PLAY_OPTIONS="--check-exact 5" TREE_OPTIONS="--root ${ROOT:-walk:0}" all alignment
make --no-print-directory -f pipelines/character.mk OUT="$out" report > /dev/null
pipeline_s=$(( $(date +%s) - t ))

echo
echo "demo: summary ($out)"
python3 pipelines/summary.py "$out" --json "$out/report/summary.json"
echo "  set-up ${setup_s} s, synth ${synth_s} s, pipeline ${pipeline_s} s; total $(( $(date +%s) - start )) s"
echo "demo: the run report is $out/report/index.html (figures, previews and a 3D viewer; open it in a browser)"
echo "demo: the character is $out/character.glb (open it in Blender or https://gltf-viewer.donmccurdy.com),"
echo "      its playback $out/previews/animation.glb and $out/previews/contact_sheet.png"
