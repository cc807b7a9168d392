#!/usr/bin/env bash
# surfcap-synth --preset studio_tiny: reconstructions with a studio's artefacts (visual hull,
# floor cut, unseen patches removed, noise, outliers, blobs) and textured OBJ frames, every
# artefact counted in the report, byte-identical on any thread count, and the model options'
# bad values refused with exit code 2.
set -euo pipefail
build=${1:?build dir}
source_dir=${2:?source dir}
synth="$build/tools/surfcap-synth"
work="$build/test-tmp/e2e-synth-studio-tiny-$$"
rm -rf "$work"
mkdir -p "$work"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$synth" --preset studio_tiny --out "$work/a" --threads 2 --log-level error

for f in capture.json cameras.json ground_truth/truth.json ground_truth/report.json ground_truth/contact_sheet.png \
         ground_truth/artefacts.png walk/mesh/000000.ply walk/textured/000000.obj walk/textured/000000.mtl \
         walk/textured/000000.png ground_truth/walk/correspondence/000000.status.npy; do
  [ -s "$work/a/$f" ] || fail "missing $f"
done
grep -q '^map_Kd 000000.png$' "$work/a/walk/textured/000000.mtl" || fail "MTL without map_Kd"
grep -q '^mtllib 000000.mtl$' "$work/a/walk/textured/000000.obj" || fail "OBJ without mtllib"
grep -q '^f [0-9]*/[0-9]* [0-9]*/[0-9]* [0-9]*/[0-9]*$' "$work/a/walk/textured/000000.obj" || fail "OBJ faces are not v/vt"
grep -q '"correspondence_status"' "$work/a/ground_truth/truth.json" || fail "truth.json names no status files"
[ -z "$(find "$work/a" -name '.*')" ] || fail "temporary files left behind"

# The report counts every artefact.
perl -MJSON::PP -e '
  local $/; open(my $f, "<", $ARGV[0]) or die; my $a = decode_json(<$f>)->{artefacts};
  printf "studio_tiny: %d frames; merged limbs in %d, holes in %d, genus != 0 in %d, blobs in %d; mean %.0f vertices\n",
    scalar @{$a->{frames}}, $a->{frames_with_merged_limbs}, $a->{frames_with_holes}, $a->{frames_with_genus_not_0},
    $a->{frames_with_blobs}, $a->{mean_vertices};
  for my $k (qw(frames_with_merged_limbs frames_with_holes frames_with_genus_not_0 frames_with_blobs frames_with_outliers)) {
    die "FAIL: no frame counted in $k\n" unless $a->{$k} > 0;
  }
' "$work/a/ground_truth/report.json"

# Same seed, one thread: byte-identical (the report's timings aside).
"$synth" --preset studio_tiny --out "$work/b" --threads 1 --log-level error
(cd "$work/a" && find . -type f ! -name report.json | sort | xargs sha256sum) > "$work/a.sum"
(cd "$work/b" && find . -type f ! -name report.json | sort | xargs sha256sum) > "$work/b.sum"
cmp -s "$work/a.sum" "$work/b.sum" || { diff "$work/a.sum" "$work/b.sum" | head; fail "not deterministic"; }

# A scene file with the models; one turned off on the command line is off.
echo '{"actor": {"vertices": 600}, "studio": {"cameras": 6, "width": 160, "height": 120},
       "reconstruction": {"model": "visual_hull", "voxel_mm": 25, "surface_tolerance_mm": 25, "vertices": 1500,
                          "floor_cut": true, "textures": true},
       "sequences": [{"name": "walk", "family": "gait", "frames": 2}]}' > "$work/small.json"
"$synth" --scene "$work/small.json" --out "$work/c" --no-images --no-textures --log-level warn
[ -s "$work/c/ground_truth/walk/correspondence/000001.status.npy" ] || fail "scene file: no status files"
[ ! -d "$work/c/walk/textured" ] || fail "--no-textures wrote textures"

# surfcap-remesh's artefact options on the true walk (one connectivity): open, status per vertex.
db="$work/a/ground_truth/database"
"$build/tools/surfcap-remesh" --template "$db/template.ply" --positions "$db/sequences/walk.npy" --out "$work/r" \
  --sequence walk --count 2 --visual-hull --voxel-mm 25 --floor-cut-mm 30 --unseen remove --outliers 0.01 \
  --blobs 1 --log-level warn 2> "$work/r.log" || { cat "$work/r.log"; fail "surfcap-remesh with artefacts"; }
[ -s "$work/r/ground_truth/walk/correspondence/000001.status.npy" ] || fail "surfcap-remesh wrote no status"
[ -s "$work/r/capture.json" ] || fail "surfcap-remesh wrote no capture.json"
[ -s "$work/r/cameras.json" ] || fail "surfcap-remesh wrote no calibration with its studio models"
n=$(perl -ne 'print $1 if /^element vertex (\d+)/' "$work/r/walk/mesh/000000.ply")
[ "$(stat -c %s "$work/r/ground_truth/walk/correspondence/000000.status.npy")" -eq $((128 + n)) ] \
  || fail "status.npy does not hold one byte per vertex"

set +e
"$synth" --preset studio_tiny --out "$work/d" --unseen sometimes 2>/dev/null; [ $? = 2 ] || fail "bad --unseen: exit code"
"$synth" --preset studio_tiny --out "$work/d" --outliers 0.9 2>/dev/null; [ $? = 2 ] || fail "bad --outliers: exit code"
echo '{"sequences": [{"name": "x", "family": "gait", "frames": 2}], "reconstruction": {"model": "laser"}}' > "$work/bad.json"
"$synth" --scene "$work/bad.json" --out "$work/d" 2>/dev/null; [ $? = 2 ] || fail "bad model: exit code"
set -e
echo "synth_studio_tiny: ok"
