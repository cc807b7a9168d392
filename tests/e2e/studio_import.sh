#!/usr/bin/env bash
# surfcap-align import-cameras / import-capture on what a studio hands over, made from the
# synthetic tiny capture: its cameras as a COLMAP text model and as OpenCV YAML come back as the
# same cameras.json calibration; its frames as a folder of numbered meshes (PLY, and textured OBJ
# with seams) become a capture.json whose histograms are byte-identical to the original's; bad
# folders give the documented exit codes.
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

# The walk frames as textured OBJ (OBJ + MTL + PNG atlas of the vertex colours: two charts split at
# x = 0, per-corner UVs, the seam vertices' positions written twice): the same histograms.
python3 - "$work/capture/walk/mesh" "$work/studio_obj/walk/mesh" <<'PY'
import glob, os, struct, sys, zlib
source, target = sys.argv[1], sys.argv[2]
os.makedirs(target)
types = {"float": "f", "double": "d", "uchar": "B", "int": "i", "uint": "I"}
def png(path, width, height, texels):
    rows = b"".join(b"\x00" + bytes(texels[y * width * 3:(y + 1) * width * 3]) for y in range(height))
    chunk = lambda kind, data: struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                           chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
for path in sorted(glob.glob(os.path.join(source, "*.ply"))):
    raw = open(path, "rb").read()
    end = raw.index(b"end_header\n") + len(b"end_header\n")
    header = raw[:end].decode().split("\n")
    nv = int([l for l in header if l.startswith("element vertex")][0].split()[2])
    nf = int([l for l in header if l.startswith("element face")][0].split()[2])
    props, vertex = [], False
    for l in header:
        if l.startswith("element"): vertex = l.startswith("element vertex")
        elif l.startswith("property") and vertex: props.append(l.split())
    fmt = "<" + "".join(types[p[1]] for p in props)
    size, names = struct.calcsize(fmt), [p[2] for p in props]
    rows = [struct.unpack_from(fmt, raw, end + i * size) for i in range(nv)]
    xyz = [tuple(r[names.index(k)] for k in "xyz") for r in rows]
    rgb = [tuple(r[names.index(k)] for k in ("red", "green", "blue")) for r in rows]
    pos, faces = end + nv * size, []
    for _ in range(nf):
        n = raw[pos]; faces.append(struct.unpack_from("<%di" % n, raw, pos + 1)); pos += 1 + 4 * n
    chart = [0 if sum(xyz[v][0] for v in f) < 0 else 1 for f in faces]
    slot = {}
    for f, c in zip(faces, chart):
        for v in f: slot.setdefault((v, c), len(slot))
    width = 64; height = (len(slot) + width - 1) // width
    texels = [255, 0, 255] * (width * height)
    for (v, c), s in slot.items(): texels[3 * s:3 * s + 3] = rgb[v]
    stem = os.path.basename(path)[:-4]
    png(os.path.join(target, stem + ".png"), width, height, texels)
    open(os.path.join(target, stem + ".mtl"), "w").write(f"newmtl skin\nKd 1 1 1\nmap_Kd {stem}.png\n")
    seam = [v for v in range(nv) if (v, 0) in slot and (v, 1) in slot]
    copy = {v: nv + k for k, v in enumerate(seam)}
    lines = [f"mtllib {stem}.mtl"] + ["v %r %r %r" % p for p in xyz] + ["v %r %r %r" % xyz[v] for v in seam]
    by_slot = sorted(slot.items(), key=lambda item: item[1])
    lines += ["vt %r %r" % ((s % width + 0.5) / width, 1 - (s // width + 0.5) / height) for _, s in by_slot]
    lines.append("usemtl skin")
    for f, c in zip(faces, chart):
        lines.append("f " + " ".join(f"{(copy[v] if c == 1 and v in copy else v) + 1}/{slot[(v, c)] + 1}" for v in f))
    open(os.path.join(target, stem + ".obj"), "w").write("\n".join(lines) + "\n")
PY
"$align" import-capture --folder "$work/studio_obj" --log-level warn
"$align" histograms --capture "$work/studio_obj" --out "$work/db_obj" --log-level warn
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
def rows(db):
    meta = json.load(open(f"{work}/{db}/similarity/histograms.json"))
    data = open(f"{work}/{db}/similarity/histograms.npy", "rb").read()
    body = data[10 + int.from_bytes(data[8:10], "little"):]
    labels = [f"{s['name']}:{s['first'] + k}" for s in meta["sequences"] for k in range(s["count"])]
    size = len(body) // len(labels)
    return {label: body[i * size:(i + 1) * size] for i, label in enumerate(labels)}
obj, synth = rows("db_obj"), rows("db_synth")
assert json.load(open(f"{work}/studio_obj/capture.json"))["sequences"][0]["frames"] == "walk/mesh/{frame:06d}.obj"
assert len(obj) == 24 and all(obj[label] == synth[label] for label in obj), "textured OBJ histograms differ"
print(f"textured OBJ form: {len(obj)} frames, histograms byte-identical to the PLY form's")
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
