#!/usr/bin/env bash
# Builds an unstructured "capture" from the dance sequence (../shared/data/dance: one
# connectivity, 201 frames) by remeshing every frame independently with surfcap-remesh (its own
# vertex count and connectivity, 1 mm noise along the normals), with ground truth in the layout of
# docs/synth.md; then, unless --no-align, aligns it with surfcap-align run and prints the error
# against the known correspondence (report/alignment.json "ground_truth").
# With artefact options the frames look like a studio's (docs/synth.md, "Studio models"):
# --floor-cut-mm H (surface within H mm of the lowest point removed: open soles), --unseen
# keep|remove|rough, --outliers F, --blobs N, --visual-hull (shape from silhouette from a ring of
# 12 cameras); --artefacts turns on all of them but the visual hull
# (--floor-cut-mm 20 --unseen remove --outliers 0.002 --blobs 1).
#
# usage: scripts/make_dance_capture.sh [--build DIR] [--out DIR] [--step K] [--count N]
#                                      [--edge-scale S] [--threads T] [--no-align]
#                                      [--artefacts] [--visual-hull] [--floor-cut-mm H]
#                                      [--unseen MODE] [--outliers F] [--blobs N]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=$here/build
out=${TMPDIR:-/tmp}/dance_capture
data=${SURFCAP_DANCE_DATA:-$here/../shared/data/dance}
step=2
count=-1
edge_scale=1.5
threads=0
align=1
studio=()
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --step) step=$2; shift 2 ;;
    --count) count=$2; shift 2 ;;
    --edge-scale) edge_scale=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --no-align) align=0; shift ;;
    --artefacts) studio+=(--floor-cut-mm 20 --unseen remove --outliers 0.002 --blobs 1); shift ;;
    --visual-hull) studio+=(--visual-hull); shift ;;
    --floor-cut-mm|--unseen|--outliers|--blobs) studio+=("$1" "$2"); shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ -f "$data/positions.npy" ] || { echo "no dance data at $data (set SURFCAP_DANCE_DATA)" >&2; exit 4; }
"$build/tools/surfcap-remesh" --template "$data/template.obj" --positions "$data/positions.npy" \
  --out "$out/capture" --sequence dance --step "$step" --count "$count" --edge-scale "$edge_scale" \
  --noise-mm 1 --seed 1 --threads "$threads" ${studio[@]+"${studio[@]}"}
[ $align -eq 1 ] || exit 0
"$build/tools/surfcap-align" run --capture "$out/capture" --out "$out/db" --threads "$threads"
perl -MJSON::PP -e '
  local $/; open(my $f, "<", $ARGV[0]) or die; my $r = decode_json(<$f>); my $g = $r->{ground_truth};
  printf "dance: %d frames, deformer %d vertices (surface + interior); RMS error %.2f mm = %.3f%% of %.2f m; worst frame %s %.2f mm (%.3f%%)\n",
    scalar @{$r->{frames}}, $r->{summary}{volume_vertices}, 1000*$g->{rms_m}, $g->{rms_percent_height}, $g->{height_m},
    $g->{worst_frame}, 1000*$g->{worst_frame_rms_m}, $g->{worst_frame_rms_percent_height};
  printf "  depth %3d: %.3f%%\n", $_->{depth}, $_->{rms_percent_height} for @{$g->{by_depth}};
' "$out/db/report/alignment.json"
