#!/usr/bin/env bash
# surfcap-synth --preset tiny: a complete capture folder in well under 20 s, byte-identical for a
# seed on any thread count, and the documented exit codes for bad arguments.
set -euo pipefail
build=${1:?build dir}
source_dir=${2:?source dir}
synth="$build/tools/surfcap-synth"
work="$build/test-tmp/e2e-synth-tiny-$$"
rm -rf "$work"
mkdir -p "$work"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$synth" --preset tiny --out "$work/a" --threads 2 --log-level warn

for f in capture.json cameras.json ground_truth/truth.json ground_truth/report.json ground_truth/contact_sheet.png \
         ground_truth/database/database.json ground_truth/database/template.ply ground_truth/template_rest.ply; do
  [ -s "$work/a/$f" ] || fail "missing $f"
done
for seq in walk run; do
  meshes=$(ls "$work/a/$seq/mesh" | wc -l)
  [ "$meshes" -ge 20 ] || fail "$seq has $meshes meshes"
  for cam in cam00 cam01 cam02 cam03; do
    images=$(ls "$work/a/$seq/images/$cam" | wc -l)
    [ "$images" = "$meshes" ] || fail "$seq/$cam has $images images for $meshes meshes"
  done
  faces=$(ls "$work/a/ground_truth/$seq/correspondence" | grep -c face.npy)
  [ "$faces" = "$meshes" ] || fail "$seq has $faces correspondence files"
done
grep -q '"format": "surfcap.capture/1"' "$work/a/capture.json" || fail "capture.json format"
[ -z "$(find "$work/a" -name '.*')" ] || fail "temporary files left behind"

# Same seed, one thread: byte-identical (the report's timings aside).
"$synth" --preset tiny --out "$work/b" --threads 1 --log-level warn
(cd "$work/a" && find . -type f ! -name report.json | sort | xargs sha256sum) > "$work/a.sum"
(cd "$work/b" && find . -type f ! -name report.json | sort | xargs sha256sum) > "$work/b.sum"
cmp -s "$work/a.sum" "$work/b.sum" || { diff "$work/a.sum" "$work/b.sum" | head; fail "not deterministic"; }

# Another seed: other reconstructions.
"$synth" --preset tiny --out "$work/c" --seed 7 --no-images --log-level warn
cmp -s "$work/a/walk/mesh/000000.ply" "$work/c/walk/mesh/000000.ply" && fail "--seed changed nothing"
[ ! -d "$work/c/walk/images" ] || fail "--no-images wrote images"
python3 - "$work/a/ground_truth/report.json" <<'PY' || fail "report.json lacks cpu_s / peak_rss_mb"
import json, sys
report = json.load(open(sys.argv[1]))
assert report["peak_rss_mb"] > 1 and report["cpu_s"] > 0, report
PY

# A cut: the first 3 frames of each sequence, the same bytes as the whole capture's.
"$synth" --preset tiny --out "$work/f" --seed 7 --no-images --frames-per-sequence 3 --log-level warn
for seq in walk run jump_low jump_high; do
  [ "$(ls "$work/f/$seq/mesh" | wc -l)" = 3 ] || fail "--frames-per-sequence 3: $seq has not 3 meshes"
  for t in 000000 000001 000002; do
    cmp -s "$work/c/$seq/mesh/$t.ply" "$work/f/$seq/mesh/$t.ply" || fail "the cut's $seq/$t differs from the whole's"
  done
done

# The long preset, cut to 2 frames of each of its 28 takes, with the images it has none of by default.
"$synth" --preset long --vertices 600 --frames-per-sequence 2 --images --out "$work/g" --log-level warn
python3 - "$work/g" <<'PY' || fail "--preset long --frames-per-sequence 2 --images"
import json, os, sys
capture = json.load(open(os.path.join(sys.argv[1], "capture.json")))
assert len(capture["sequences"]) == 28 and all(s["count"] == 2 for s in capture["sequences"]), capture["sequences"]
assert all(s.get("images") for s in capture["sequences"])
assert os.path.exists(os.path.join(sys.argv[1], "reach_top/images/cam07/000001.png"))
PY

# Exit codes: 2 for bad arguments.
set +e
"$synth" --preset nope --out "$work/d" 2>/dev/null; [ $? = 2 ] || fail "unknown preset: exit code"
"$synth" --preset tiny --frames-per-sequence 1 --out "$work/d" 2>/dev/null; [ $? = 2 ] || fail "cut of 1: exit code"
"$synth" --scene "$work/missing.json" --out "$work/d" 2>/dev/null; [ $? = 2 ] || fail "missing scene: exit code"
echo '{"sequences": [{"name": "x", "frames": 1}]}' > "$work/bad.json"
"$synth" --scene "$work/bad.json" --out "$work/d" 2>/dev/null; [ $? = 2 ] || fail "bad scene: exit code"
"$synth" --scene "$source_dir/configs/synth/tiny.json" --out "$work/e" --no-images --vertices 600 --log-level warn
[ $? = 0 ] || fail "--scene configs/synth/tiny.json failed"
set -e
echo "synth_tiny: ok"
