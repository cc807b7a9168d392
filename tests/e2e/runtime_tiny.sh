#!/usr/bin/env bash
# The runtime end to end on the synthetic tiny capture: synth → align (geometry only, one level:
# accuracy is align_tiny's business; this keeps it to seconds) → learn → precompute spaces →
# transitions (whole and sharded: same bytes) → export → play a timeline with --check-exact:
# every checked frame within ε of the exact non-linear blend, the outputs, the report and the
# exit codes. Usage: bash runtime_tiny.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
tools=$build/tools
source "$(dirname "$0")/support/common.bash"
require_tools surfcap-synth surfcap-align surfcap-learn surfcap-precompute surfcap-play
work=$(mktemp -d "$build/runtime_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
graph_config=$source/configs/graphs/tiny.json

"$tools/surfcap-synth" --preset tiny --no-images --out "$work/capture" --threads 2 > "$work/log" 2>&1
"$tools/surfcap-align" --threads 2 run --capture "$work/capture" --out "$work/db" --no-images --levels 1 \
  --rotation-iterations 1 --dense-iterations 1 --surface-model --log-level warn >> "$work/log" 2>&1
database=$work/db/database.json
"$tools/surfcap-learn" --threads 2 learn --database "$database" --parts "$source/configs/parts/human6.json" \
  --examples 8 --output "$work/model" >> "$work/log" 2>&1
"$tools/surfcap-precompute" --threads 2 spaces --database "$database" --graph "$graph_config" --output "$work/out" \
  --sweep-mm 5 --validation-samples 2 >> "$work/log" 2>&1
"$tools/surfcap-precompute" --threads 2 transitions --database "$database" --graph "$graph_config" \
  --output "$work/out" >> "$work/log" 2>&1
for f in locomotion__jump.npy locomotion__jump.json locomotion__jump.png jump__locomotion.npy jump__locomotion.json; do
  test -s "$work/out/transitions/$f" || { echo "missing transitions/$f"; exit 1; }
done
test -s "$work/out/report/transitions.json"

# A sharded run (one edge, one thread) gives the same bytes.
mkdir -p "$work/shard"
cp -r "$work/out/spaces" "$work/shard/"
"$tools/surfcap-precompute" --threads 1 transitions --database "$database" --graph "$graph_config" \
  --output "$work/shard" --edge locomotion:jump >> "$work/log" 2>&1
cmp "$work/out/transitions/locomotion__jump.npy" "$work/shard/transitions/locomotion__jump.npy"
test -s "$work/shard/report/transitions_locomotion__jump.json"
test ! -e "$work/shard/transitions/jump__locomotion.npy"

python3 - "$work/out" <<'PY'
import json, struct, sys
out = sys.argv[1]
meta = json.load(open(out + "/transitions/locomotion__jump.json"))
assert meta["format"] == "surfcap.transition/1", meta
graph = json.load(open(out + "/graph.json"))
spaces = {s["name"]: s for s in graph["spaces"]}
rows = len(spaces["locomotion"]["coordinates"]) * spaces["locomotion"]["frames"]
cols = len(spaces["jump"]["coordinates"]) * spaces["jump"]["frames"]
assert (meta["rows"], meta["cols"]) == (rows, cols), (meta["rows"], meta["cols"], rows, cols)
data = open(out + "/transitions/locomotion__jump.npy", "rb").read()
header_length = struct.unpack("<H", data[8:10])[0]
values = struct.unpack("<%df" % (rows * cols), data[10 + header_length:])
assert min(values) >= 0 and max(values) <= 1 and abs(min(values)) < 1e-6, (min(values), max(values))
# Shape + motion: walking is closer to the jump's ground phases (take-off, landing) than to its apex.
T = spaces["jump"]["frames"]
per_frame = [0.0] * T
for k, value in enumerate(values):
    per_frame[(k % cols) % T] += value
ground = (sum(per_frame[:3]) + sum(per_frame[-3:])) / 6
apex = sum(per_frame[T // 2 - 1:T // 2 + 2]) / 3
assert ground > apex * 1.2, (ground, apex)
PY

# Export (surfcap-export, from the asset module) when built; else play from the build outputs.
character=(--database "$database" --graph "$work/out/graph.json")
if [[ -x $tools/surfcap-export ]]; then
  "$tools/surfcap-export" --database "$database" --graph "$work/out/graph.json" --parts "$work/model/parts.json" \
    --output "$work/character.glb" >> "$work/log" 2>&1
  character=(--character "$work/character.glb")
else
  echo "note: surfcap-export is not built; playing from database.json + graph.json"
fi
"$tools/surfcap-play" --threads 2 "${character[@]}" --script "$source/configs/control/tiny_timeline.json" \
  --output "$work/play" --check-exact 3 >> "$work/log" 2>&1
python3 - "$work/play" <<'PY'
import json, sys
play = sys.argv[1]
report = json.load(open(play + "/report.json"))
assert report["format"] == "surfcap.report/1" and report["stage"] == "play"
assert report["frames"] == 100, report["frames"]
check = report["check_exact"]
assert check["frames_checked"] == 34, check
assert check["max_error_mm"] <= check["tolerance_mm"], check
spaces = [(t["from"], t["to"]) for t in report["transitions"]]
assert ("locomotion", "jump") in spaces and ("jump", "locomotion") in spaces, spaces
for t in report["transitions"]:
    assert t["latency_frames"] <= 20 and 0 < t["similarity"] <= 1, t
glb = open(play + "/animation.glb", "rb").read()
assert glb[:4] == b"glTF", glb[:4]
assert open(play + "/contact_sheet.png", "rb").read()[:4] == b"\x89PNG"
print("runtime_tiny: %d frames, transitions %s, max error vs exact %.2f mm (ε %.1f mm), %.1f µs CPU per frame"
      % (report["frames"], spaces, check["max_error_mm"], check["tolerance_mm"], 1e6 * report["evaluation_cpu_per_frame_s"]))
PY

# Same inputs, other thread count: the same animation and contact sheet, byte for byte.
"$tools/surfcap-play" --threads 1 "${character[@]}" --script "$source/configs/control/tiny_timeline.json" \
  --output "$work/play1" >> "$work/log" 2>&1
cmp "$work/play/animation.glb" "$work/play1/animation.glb"
cmp "$work/play/contact_sheet.png" "$work/play1/contact_sheet.png"

# Bad input and bad arguments: the documented exit codes, the file named.
set +e
echo '{"format": "surfcap.control/1", "duration_s": 1, "start": {"space": "swim"}}' > "$work/bad_space.json"
"$tools/surfcap-play" "${character[@]}" --script "$work/bad_space.json" --output "$work/bad" 2> "$work/err"
[[ $? -eq 3 ]] || { echo "unknown space must exit 3"; exit 1; }
grep -q "bad_space.json" "$work/err" || { echo "the error must name the control file"; cat "$work/err"; exit 1; }
echo '{"format": "surfcap.control/1", "duration_s": 1, "start": {"space": "jump", "parameters": {"speed": 2}}}' \
  > "$work/bad_parameter.json"
"$tools/surfcap-play" "${character[@]}" --script "$work/bad_parameter.json" --output "$work/bad" 2> "$work/err"
[[ $? -eq 3 ]] || { echo "unknown parameter must exit 3"; exit 1; }
"$tools/surfcap-play" "${character[@]}" --script "$source/configs/control/tiny_timeline.json"
[[ $? -eq 2 ]] || { echo "missing --output must exit 2"; exit 1; }
"$tools/surfcap-precompute" transitions --database "$database" --graph "$graph_config" --output "$work/out" \
  --edge jump:nowhere
[[ $? -eq 2 ]] || { echo "undeclared --edge must exit 2"; exit 1; }
python3 - "$work/out/graph.json" "$work/out/bad_graph.json" <<'PY'
import json, sys
graph = json.load(open(sys.argv[1]))
graph["spaces"][0]["sequences"][0]["name"] = "nope"
json.dump(graph, open(sys.argv[2], "w"))
PY
"$tools/surfcap-play" --database "$database" --graph "$work/out/bad_graph.json" \
  --script "$source/configs/control/tiny_timeline.json" --output "$work/bad" 2> "$work/err"
[[ $? -eq 3 ]] || { echo "a space over a missing sequence must exit 3"; exit 1; }
grep -q "bad_graph.json" "$work/err" || { echo "the error must name graph.json"; cat "$work/err"; exit 1; }
rm "$work/out/transitions/jump__locomotion.npy"
"$tools/surfcap-play" --database "$database" --graph "$work/out/graph.json" \
  --script "$source/configs/control/tiny_timeline.json" --output "$work/bad" 2> "$work/err"
[[ $? -eq 3 ]] || { echo "a missing declared transition must exit 3"; exit 1; }
grep -q "jump__locomotion.npy" "$work/err" || { echo "the error must name the missing file"; cat "$work/err"; exit 1; }
echo "runtime_tiny: ok"
