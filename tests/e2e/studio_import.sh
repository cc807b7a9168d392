#!/usr/bin/env bash
# surfcap-align import-cameras / import-capture on what a studio hands over, made from the
# synthetic tiny capture: its cameras as a COLMAP text model and as OpenCV YAML come back as the
# same cameras.json calibration; its frames as a folder of numbered meshes become a capture.json
# whose histograms are byte-identical to the original's; bad folders give the documented exit codes.
# Usage: bash studio_import.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
synth=$build/tools/surfcap-synth
align=$build/tools/surfcap-align
if [[ ! -x $synth || ! -x $align ]]; then
  echo "SKIP: surfcap-synth or surfcap-align is not built"
  exit 77
fi
work=$(mktemp -d "$build/studio_import_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$synth" --preset tiny --seed 5 --no-images --out "$work/capture" --log-level warn

# The calibration as COLMAP (cameras.txt + images.txt) and OpenCV FileStorage YAML would write it.
python3 - "$work/capture/cameras.json" "$work/colmap" "$work/rig.yml" <<'PY'
import json, math, os, sys
cameras = json.load(open(sys.argv[1]))["cameras"]
os.makedirs(sys.argv[2])
def quaternion(R):  # rotation matrix (row-major 9) → (w, x, y, z)
    m = [R[0:3], R[3:6], R[6:9]]
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0:
        s = 0.5 / math.sqrt(trace + 1.0)
        return (0.25 / s, (m[2][1] - m[1][2]) * s, (m[0][2] - m[2][0]) * s, (m[1][0] - m[0][1]) * s)
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + m[i][i] - m[j][j] - m[k][k])
    q = [0.0] * 4
    q[0] = (m[k][j] - m[j][k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (m[j][i] + m[i][j]) / s
    q[1 + k] = (m[k][i] + m[i][k]) / s
    return tuple(q)
with open(os.path.join(sys.argv[2], "cameras.txt"), "w") as out, open(os.path.join(sys.argv[2], "images.txt"), "w") as images:
    for n, c in enumerate(cameras, 1):
        K, d = c["K"], c["dist"]
        params = [K[0], K[4], K[2] + 0.5, K[5] + 0.5] + d[:4]  # COLMAP: the top-left pixel's centre at (0.5, 0.5)
        out.write(f"{n} OPENCV {c['width']} {c['height']} " + " ".join(repr(v) for v in params) + "\n")
        images.write(f"{n} " + " ".join(repr(v) for v in quaternion(c["R"]) + tuple(c["t"])) + f" {n} {c['name']}/000000.png\n\n")
with open(sys.argv[3], "w") as out:
    out.write("%YAML:1.0\n---\n")
    def matrix(key, rows, cols, values):
        out.write(f"   {key}: !!opencv-matrix\n      rows: {rows}\n      cols: {cols}\n      dt: d\n")
        out.write("      data: [ " + ", ".join(repr(v) for v in values) + " ]\n")
    for c in cameras:
        out.write(f"{c['name']}:\n")
        matrix("camera_matrix", 3, 3, c["K"])
        matrix("distortion_coefficients", 1, 5, c["dist"])
        matrix("R", 3, 3, c["R"])
        matrix("T", 3, 1, [1000.0 * v for v in c["t"]])  # millimetres
        out.write(f"   image_width: {c['width']}\n   image_height: {c['height']}\n")
PY
"$align" import-cameras --colmap "$work/colmap" --out "$work/from_colmap/cameras.json" --log-level warn
"$align" import-cameras --opencv "$work/rig.yml" --scale 0.001 --out "$work/from_opencv/cameras.json" --log-level warn
python3 - "$work/capture/cameras.json" "$work/from_colmap/cameras.json" "$work/from_opencv/cameras.json" <<'PY'
import json, sys
def project(c, X):  # OpenCV model, as docs/formats.md states it
    R, t, K, d = c["R"], c["t"], c["K"], c["dist"]
    p = [sum(R[3 * r + k] * X[k] for k in range(3)) + t[r] for r in range(3)]
    x, y = p[0] / p[2], p[1] / p[2]
    r2 = x * x + y * y
    radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]))
    xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x)
    yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y
    return K[0] * xd + K[1] * yd + K[2], K[4] * yd + K[5]
truth = json.load(open(sys.argv[1]))["cameras"]
points = [(x / 4, 0.2 + y / 4, z / 4) for x in range(-2, 3) for y in range(0, 7) for z in range(-2, 3)]
for path in sys.argv[2:]:
    imported = json.load(open(path))["cameras"]
    assert [c["name"] for c in imported] == [c["name"] for c in truth], path
    worst = max(max(abs(a - b) for a, b in zip(project(c, X), project(i, X))) for c, i in zip(truth, imported) for X in points)
    print(f"{path.split('/')[-2]}: {len(imported)} cameras, worst projection difference {worst:.2e} px")
    assert worst < 1e-6, worst
PY
[[ -f $work/from_colmap/report/import-cameras.json ]] || { echo "no import-cameras report"; exit 1; }

# The frames as a studio folder: walk as <seq>/mesh/000000.ply..., run as run/run_<n>.ply (unpadded).
studio=$work/studio
mkdir -p "$studio/walk/mesh" "$studio/run"
cp "$work/capture"/walk/mesh/*.ply "$studio/walk/mesh/"
for file in "$work/capture"/run/mesh/*.ply; do
  number=$(basename "$file" .ply)
  cp "$file" "$studio/run/run_$((10#$number)).ply"
done
"$align" import-capture --folder "$studio" --calibration "$work/from_colmap/cameras.json" --fps 25 --log-level warn
"$align" histograms --capture "$studio" --out "$work/db_studio" --log-level warn
"$align" histograms --capture "$work/capture" --out "$work/db_synth" --log-level warn
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
def rows(db):  # histograms.npy rows by frame label
    meta = json.load(open(f"{work}/{db}/similarity/histograms.json"))
    data = open(f"{work}/{db}/similarity/histograms.npy", "rb").read()
    header = int.from_bytes(data[8:10], "little")
    body = data[10 + header:]
    labels = [f"{s['name']}:{s['first'] + k}" for s in meta["sequences"] for k in range(s["count"])]
    size = len(body) // len(labels)
    return {label: body[i * size:(i + 1) * size] for i, label in enumerate(labels)}
studio, synth = rows("db_studio"), rows("db_synth")
capture = json.load(open(f"{work}/studio/capture.json"))
assert [s["name"] for s in capture["sequences"]] == ["run", "walk"], capture
assert capture["sequences"][0]["frames"] == "run/run_{frame}.ply", capture
assert all(studio[label] == synth[label] for label in studio), "histograms differ"
print(f"imported capture: {len(studio)} frames, histograms byte-identical to the original capture's")
PY

# Bad folders: capture.json exists (exit 2), a gap in the numbers and an unknown COLMAP model (exit 3).
set +e
"$align" import-capture --folder "$studio" --log-level warn 2> "$work/err.txt"; exists=$?
rm "$studio/capture.json" "$studio/run/run_3.ply"
"$align" import-capture --folder "$studio" --log-level warn 2> "$work/gap.txt"; gap=$?
sed -i 's/ OPENCV / OPENCV_FISHEYE /' "$work/colmap/cameras.txt"
"$align" import-cameras --colmap "$work/colmap" --out "$work/bad/cameras.json" --log-level warn 2> "$work/model.txt"; model=$?
set -e
[[ $exists -eq 2 ]] || { echo "existing capture.json: exit $exists"; exit 1; }
[[ $gap -eq 3 ]] && grep -q "frame 3 is missing" "$work/gap.txt" || { echo "gap: exit $gap"; cat "$work/gap.txt"; exit 1; }
[[ $model -eq 3 ]] && grep -q "cameras.txt': line 1: camera model OPENCV_FISHEYE" "$work/model.txt" \
  || { echo "fisheye: exit $model"; cat "$work/model.txt"; exit 1; }
[[ ! -e $work/bad/cameras.json && ! -e $studio/capture.json ]] || { echo "a failed import left an output"; exit 1; }
echo "studio_import: ok"
