#!/usr/bin/env bash
# The whole demo on a fresh machine: set-up, a synthetic capture, the pipeline, a summary.
# Usage: scripts/demo.sh [OUT_DIR]   (default out/demo)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
./scripts/setup.sh
out=${1:-out/demo}
bin=build/tools
rm -rf "$out"
mkdir -p "$out"
declare -A seconds
run_stage() {  # run_stage NAME command...
  local name=$1 t
  shift
  t=$(date +%s)
  echo "demo: $name"
  "$@"
  seconds[$name]=$(( $(date +%s) - t ))
}

run_stage synth "$bin/surfcap-synth" --preset demo --seed 1 --out "$out/capture" --log-level warn
capture=$out/capture
run_stage align.histograms "$bin/surfcap-align" histograms --capture "$capture" --out "$out/aligned" --log-level warn
run_stage align.similarity "$bin/surfcap-align" similarity --out "$out/aligned" --log-level warn
run_stage align.tree "$bin/surfcap-align" tree --out "$out/aligned" --log-level warn \
  --ground-truth "$capture/ground_truth/database/database.json"

run_stage align.register "$bin/surfcap-align" register --capture "$capture" --out "$out/aligned" --log-level warn
# The alignment does not reach its accuracy bound yet (issue 5), so the later stages run on the
# capture's true aligned database; set SURFCAP_DEMO_USE_ALIGNED=1 to use the registered one.
database=$capture/ground_truth/database/database.json
[[ ${SURFCAP_DEMO_USE_ALIGNED:-0} == 1 ]] && database=$out/aligned/database.json
echo "demo: later stages read $database"
run_stage learn "$bin/surfcap-learn" learn --database "$database" --parts configs/parts/human6.json \
  --output "$out/parts" --log-level warn
run_stage precompute.spaces "$bin/surfcap-precompute" spaces --database "$database" \
  --graph configs/graphs/demo.json --output "$out/spaces" --log-level warn

echo
echo "demo: summary"
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
def load(path):
    path = os.path.join(out, path)
    return json.load(open(path)) if os.path.exists(path) else None
tree = load("aligned/report/similarity.json")
if tree:
    q = tree.get("quality", {})
    print(f"  similarity tree: {tree['frames']} frames, root {tree['root']}, "
          f"quality ratio {q.get('ratio', float('nan')):.3f} (true deformation along the tree / optimal)")
alignment = load("aligned/report/alignment.json")
if alignment and "ground_truth" in alignment:
    g = alignment["ground_truth"]
    print(f"  alignment: RMS vertex error {g['rms_percent_height']:.2f}% of height, worst frame "
          f"{g['worst_frame']} {g['worst_frame_rms_percent_height']:.2f}%, mean residual "
          f"{alignment['summary']['mean_residual_m'] * 1000:.2f} mm")
learn = load("parts/report/learn.json")
if learn:
    parts = learn.get("parts", {})
    print(f"  part models: {len(parts)} parts, basis vectors kept " +
          ", ".join(f"{name} {part.get('kept')}" for name, part in sorted(parts.items())))
spaces = load("spaces/report/spaces.json")
for name, space in sorted((spaces or {}).get("spaces", {}).items()):
    print(f"  motion space {name}: {space.get('references')} references, hybrid max error "
          f"{space.get('checked_max_error_mm', float('nan')):.2f} mm at tolerance {space.get('tolerance_mm')} mm, "
          f"{space.get('memory_bytes', 0) / 1e6:.1f} MB of displacement fields")
PY
for name in "${!seconds[@]}"; do echo "  $name: ${seconds[$name]} s"; done | sort
echo "demo: finished in $(( $(date +%s) - start )) s. Previews and reports:"
find "$out" \( -name '*.png' -o -name '*.glb' \) -not -path '*/images/*' 2>/dev/null | sort | head -30
find "$out" -path '*report*' -name '*.json' | sort | head -20
