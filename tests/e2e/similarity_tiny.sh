#!/usr/bin/env bash
# surfcap-align histograms → similarity (whole and sharded) → merge → tree on the synthetic tiny
# capture: sharded + merged matrix is byte-identical to the whole one, outputs do not depend on
# the thread count, the tree spans every frame, its quality against the ground truth is within
# the issue's bound, and bad input gives the documented exit codes.
# Usage: bash similarity_tiny.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
synth=$build/tools/surfcap-synth
align=$build/tools/surfcap-align
if [[ ! -x $synth || ! -x $align ]]; then
  echo "SKIP: surfcap-synth or surfcap-align is not built"
  exit 77
fi
work=$(mktemp -d "$build/similarity_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$synth" --preset tiny --seed 3 --no-images --out "$work/capture" --log-level warn

"$align" histograms --capture "$work/capture" --out "$work/a" --threads 2 --log-level warn
"$align" histograms --capture "$work/capture" --out "$work/b" --threads 1 --log-level warn
cmp "$work/a/similarity/histograms.npy" "$work/b/similarity/histograms.npy"

"$align" similarity --out "$work/a" --log-level warn
n=$(python3 -c "import json; print(sum(s['count'] for s in json.load(open('$work/a/similarity/histograms.json'))['sequences']))")
half=$((n / 2))
"$align" similarity --out "$work/b" --rows "0:$half" --threads 1 --log-level warn
"$align" similarity --out "$work/b" --rows "$half:$n" --log-level warn
"$align" merge --out "$work/b" --log-level warn
cmp "$work/a/similarity/matrix.npy" "$work/b/similarity/matrix.npy"
# Every stage's report, merge's too, gives the process's CPU time and peak memory.
python3 - "$work/b/report" <<'PY'
import json, os, sys
names = sorted(os.listdir(sys.argv[1]))
assert "similarity-merge.json" in names and "histograms.json" in names, names
for name in names:
    report = json.load(open(os.path.join(sys.argv[1], name)))
    assert report["format"] == "surfcap.report/1" and report["peak_rss_mb"] > 1 and report["cpu_s"] > 0, (name, report)
PY

"$align" tree --out "$work/a" --ground-truth "$work/capture/ground_truth/database/database.json" --log-level warn
python3 - "$work/a" "$n" <<'PY'
import json, sys
folder, n = sys.argv[1], int(sys.argv[2])
tree = json.load(open(f"{folder}/similarity/tree.json"))
report = json.load(open(f"{folder}/report/similarity.json"))
edges = tree["edges"]
assert len(edges) == n - 1, f"{len(edges)} edges for {n} frames"
reached = {tree["root"]["node"]}
for edge in edges:  # breadth-first: parents come first, every frame once
    assert edge["parent"] in reached and edge["child"] not in reached, edge
    reached.add(edge["child"])
assert len(reached) == n
ratio = report["quality"]["ratio"]
print(f"tree quality ratio {ratio:.3f} over {n} frames")
assert 1.0 <= ratio <= 1.3, ratio
PY

# Bad input: a missing frame (exit 3, names the file), a missing capture (exit 4), bad rows (exit 2).
rm "$work/capture/$(python3 -c "import json; s=json.load(open('$work/capture/capture.json'))['sequences'][0]; print(s['frames'].replace('{frame:06d}', '%06d' % (s['first'] + 1)))")"
set +e
"$align" histograms --capture "$work/capture" --out "$work/c" 2> "$work/err.txt"; code=$?
"$align" histograms --capture "$work/nothing" --out "$work/c" 2> /dev/null; missing=$?
"$align" similarity --out "$work/a" --rows "5:2" 2> /dev/null; rows=$?
set -e
[[ $code -eq 3 ]] || { echo "missing frame: exit $code"; exit 1; }
grep -q "000001" "$work/err.txt" || { echo "the error does not name the frame"; cat "$work/err.txt"; exit 1; }
[[ $missing -eq 4 ]] || { echo "missing capture: exit $missing"; exit 1; }
[[ $rows -eq 2 ]] || { echo "bad rows: exit $rows"; exit 1; }
[[ ! -e "$work/c/similarity/histograms.npy" ]] || { echo "a failed run left an output"; exit 1; }
echo "similarity e2e: ok"
