#!/usr/bin/env bash
# surfcap-precompute spaces on the synthetic tiny capture's ground-truth database: outputs of
# DESIGN §3.4 exist, the hybrid stays within tolerance, sharding by --space works and reruns are
# byte-identical. Usage: bash blend_spaces.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
precompute=$build/tools/surfcap-precompute
synth=$build/tools/surfcap-synth
if [[ ! -x $synth ]]; then
  echo "SKIP: surfcap-synth is not built (the blend unit tests cover the library on procedural data)"
  exit 77
fi
work=$(mktemp -d "$build/blend_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$synth" --preset tiny --no-images --out "$work/capture" --threads 2
database=$work/capture/ground_truth/database/database.json
test -f "$database"

"$precompute" --threads 2 spaces --database "$database" --graph "$source/configs/graphs/tiny.json" \
  --output "$work/out" --sweep-mm 5 20 --validation-samples 4
for f in graph.json spaces/locomotion/space.json spaces/locomotion/references.npy spaces/locomotion/warp.npy \
  spaces/locomotion/warp.png spaces/locomotion/root.npy spaces/locomotion/displacements.offsets.npy \
  spaces/locomotion/displacements.vertices.npy spaces/locomotion/displacements.values.npy report/spaces.json; do
  test -s "$work/out/$f" || { echo "missing $f"; exit 1; }
done
python3 - "$work/out" <<'PY'
import json, sys
out = sys.argv[1]
graph = json.load(open(out + "/graph.json"))
assert graph["format"] == "surfcap.graph/1", graph["format"]
space = graph["spaces"][0]
assert space["max_error_mm"] <= space["tolerance_mm"], space["max_error_mm"]
report = json.load(open(out + "/report/spaces.json"))
figures = report["spaces"]["locomotion"]
assert figures["validation"]["hybrid_max_error_mm"] <= 5.0, figures["validation"]
assert figures["parameter_map"]["residual_max"] < 0.1, figures["parameter_map"]
print("locomotion:", figures["references"], "references,", figures["memory_bytes"], "bytes, linear",
      round(figures["validation"]["linear_max_error_mm"], 2), "mm vs hybrid",
      round(figures["validation"]["hybrid_max_error_mm"], 2), "mm")
PY

# Sharded run of the same space: byte-identical space files.
"$precompute" --threads 1 spaces --database "$database" --graph "$source/configs/graphs/tiny.json" \
  --output "$work/shard" --space locomotion --sweep-mm 5 20 --validation-samples 4
for f in space.json references.npy warp.npy warp.png displacements.offsets.npy displacements.vertices.npy \
  displacements.values.npy; do
  cmp "$work/out/spaces/locomotion/$f" "$work/shard/spaces/locomotion/$f"
done
# graph.json appears once every space of the config is there (tiny has two: locomotion, jump).
[[ ! -e $work/shard/graph.json ]] || { echo "graph.json written before the jump space"; exit 1; }
"$precompute" --threads 1 spaces --database "$database" --graph "$source/configs/graphs/tiny.json" \
  --output "$work/shard" --space jump --sweep-mm 5 20 --validation-samples 4
cmp "$work/out/graph.json" "$work/shard/graph.json"

# Bad arguments and bad input give the documented exit codes.
set +e
"$precompute" spaces --database "$database" --graph "$source/configs/graphs/tiny.json" --output "$work/x" --space nope
[[ $? -eq 2 ]] || { echo "unknown --space must exit 2"; exit 1; }
echo '{"format": "surfcap.graph_config/1", "spaces": [{"name": "s", "sequences": ["walk", "nope"]}]}' > "$work/bad.json"
"$precompute" spaces --database "$database" --graph "$work/bad.json" --output "$work/x"
[[ $? -eq 3 ]] || { echo "unknown sequence must exit 3"; exit 1; }
echo "blend_spaces: ok"
