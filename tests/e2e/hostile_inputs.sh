#!/usr/bin/env bash
# Hostile and broken inputs across the seven tools, by class (docs/reliability.md "Hostile
# inputs"): crashes (deep JSON, out-of-range indices), hangs (FIFOs, devices, huge coordinates),
# runaway memory (requests beyond --max-memory), reads and writes outside the folders the user
# named (paths and names in every document kind), bad input accepted, bad input reported as an
# internal error or without its file, and valid input refused. Each case must end in the
# documented exit code within the case timeout, name the file (and field), and leave no output
# under a final name; nothing may appear outside the case folder.
# Usage: bash hostile_inputs.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
tools=$build/tools
source "$(dirname "$0")/support/common.bash"
require_tools surfcap-synth surfcap-align surfcap-learn surfcap-precompute surfcap-edit surfcap-export surfcap-play
work=$(mktemp -d "${TMPDIR:-/tmp}/hostile_inputs.XXXXXX")
# SURFCAP_KEEP_VALID=DIR keeps a copy of the valid inputs (e.g. to seed the fuzz corpus).
trap '[[ -z ${SURFCAP_KEEP_VALID:-} ]] || cp -a "$valid" "$SURFCAP_KEEP_VALID"; rm -rf "$work"' EXIT
valid=$work/valid
quiet=(--log-level error --threads 2)
"$tools/surfcap-synth" --preset tiny --no-images --out "$valid/capture" "${quiet[@]}"
gt=$valid/capture/ground_truth/database
"$tools/surfcap-learn" learn --database "$gt/database.json" --parts "$source/configs/parts/human6.json" \
  --examples 8 --output "$valid/model" "${quiet[@]}"
cp "$source/configs/graphs/tiny.json" "$valid/graph.json"
cp "$source/configs/parts/human6.json" "$valid/part_config.json"
cp "$source/configs/control/tiny_timeline.json" "$valid/control.json"
"$tools/surfcap-precompute" "${quiet[@]}" spaces --database "$gt/database.json" --graph "$valid/graph.json" \
  --output "$valid/built" --validation-samples 2
"$tools/surfcap-precompute" "${quiet[@]}" transitions --database "$gt/database.json" --graph "$valid/graph.json" \
  --output "$valid/built"
"$tools/surfcap-export" --database "$gt/database.json" --graph "$valid/built/graph.json" \
  --parts "$valid/model/parts.json" --output "$valid/character.glb" "${quiet[@]}"
cat > "$valid/edit.json" << 'JSON'
{"format": "surfcap.edit/1", "anchors": [{"part_core": "torso"}], "handles": [{"region": "foot_l", "translate": [0, 0.05, 0]}]}
JSON
source "$(dirname "$0")/support/catalogue.bash"
declare -A per_class=()
count() { per_class[$1]=$(( ${per_class[$1]:-0} + 1 )); }

# The tools, on the case copy ($case), writing into $case/out.
db() { echo "$case/capture/ground_truth/database"; }
histograms() { "$tools/surfcap-align" histograms --capture "$case/capture" --out "$case/out" "${quiet[@]}" "$@"; }
learn() { "$tools/surfcap-learn" learn --database "$(db)/database.json" --parts "$case/part_config.json" \
  --examples 8 --output "$case/out" "${quiet[@]}" "$@"; }
spaces() { "$tools/surfcap-precompute" "${quiet[@]}" "$@" spaces --database "$(db)/database.json" --graph "$case/graph.json" \
  --output "$case/out" --validation-samples 2; }
export_glb() { "$tools/surfcap-export" --database "$(db)/database.json" --graph "$case/built/graph.json" \
  --parts "$case/model/parts.json" --output "$case/out/character.glb" "${quiet[@]}" "$@"; }
play() { "$tools/surfcap-play" --character "$case/character.glb" --script "$case/control.json" --output "$case/out" \
  "${quiet[@]}" "$@"; }
play_built() { "$tools/surfcap-play" --database "$(db)/database.json" --graph "$case/built/graph.json" \
  --script "$case/control.json" --output "$case/out" "${quiet[@]}" "$@"; }
edit() { "$tools/surfcap-edit" --model "$case/model/parts.json" --edit "$case/edit.json" --output "$case/out/edited.ply" \
  "${quiet[@]}" "$@"; }

# Helpers that craft the inputs (python: no numpy needed).
deep() { python3 -c "import sys; n = int(sys.argv[1]); sys.stdout.write('[' * n + ']' * n)" "${1:-1000000}"; }
nest_field() {  # file python-path: replaces d<python-path> by 10^6 nested arrays (text, not json.dump)
  py "$1" "$2" << 'PY'
import json, sys
d = json.load(open(sys.argv[1]))
exec("d" + sys.argv[2] + " = '@DEEP@'")
open(sys.argv[1], "w").write(json.dumps(d).replace('"@DEEP@"', "[" * 10**6 + "]" * 10**6))
PY
}
glb_json() {  # file python-statement on the JSON chunk `j` ('@DEEP@' strings become 10^6 nested arrays)
  py "$1" "$2" << 'PY'
import json, struct, sys
raw = open(sys.argv[1], "rb").read()
magic, version, _ = struct.unpack("<III", raw[:12])
length, kind = struct.unpack("<II", raw[12:20])
j = json.loads(raw[20:20 + length])
rest = raw[20 + length:]
exec(sys.argv[2])
text = json.dumps(j).replace('"@DEEP@"', "[" * 10**6 + "]" * 10**6).encode()
text += b" " * (-len(text) % 4)
open(sys.argv[1], "wb").write(struct.pack("<III", magic, version, 20 + len(text) + len(rest)) +
                              struct.pack("<II", len(text), kind) + text + rest)
PY
}
npy_scale() {  # file factor: multiplies every float32 of a .npy
  py "$1" "$2" << 'PY'
import struct, sys
raw = open(sys.argv[1], "rb").read()
h = 10 + struct.unpack("<H", raw[8:10])[0]
n = (len(raw) - h) // 4
values = [v * float(sys.argv[2]) for v in struct.unpack("<%df" % n, raw[h:])]
open(sys.argv[1], "wb").write(raw[:h] + struct.pack("<%df" % n, *values))
PY
}
ply_scale() {  # binary PLY frame (as surfcap-synth writes them): multiplies x, y, z by a factor
  py "$1" "$2" << 'PY'
import struct, sys
raw = open(sys.argv[1], "rb").read()
end = raw.index(b"end_header\n") + len(b"end_header\n")
lines = raw[:end].decode().split("\n")
nv = int([l for l in lines if l.startswith("element vertex")][0].split()[2])
props = [l for l in lines if l.startswith("property") and "list" not in l]
vsize = sum(4 if l.split()[1] in ("float", "int") else 1 for l in props)
out = bytearray(raw)
for v in range(nv):
    p = end + v * vsize
    x, y, z = struct.unpack("<3f", raw[p:p + 12])
    out[p:p + 12] = struct.pack("<3f", *(c * float(sys.argv[2]) for c in (x, y, z)))
open(sys.argv[1], "wb").write(bytes(out))
PY
}
prism() {  # path format count_type index_type: a closed prism with two 300-gon caps (PLY or OBJ)
  py "$@" << 'PY'
import math, struct, sys
path, fmt = sys.argv[1], sys.argv[2]
n = 300
verts = [(0.3 * math.cos(2 * math.pi * k / n), y, -0.3 * math.sin(2 * math.pi * k / n)) for y in (0.0, 1.6) for k in range(n)]
faces = [list(range(n - 1, -1, -1)), list(range(n, 2 * n))]
faces += [[k, (k + 1) % n, n + (k + 1) % n, n + k] for k in range(n)]
if fmt == "obj":
    with open(path, "w") as f:
        f.writelines("v %f %f %f\n" % v for v in verts)
        f.writelines("f " + " ".join(str(i + 1) for i in face) + "\n" for face in faces)
    sys.exit()
count_type, index_type = sys.argv[3], sys.argv[4]
codes = {"uchar": "B", "ushort": "H", "uint": "I", "int": "i", "short": "h"}
order = ">" if fmt == "binary_big_endian" else "<"
header = "ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n" \
         "element face %d\nproperty list %s %s vertex_indices\nend_header\n" % (fmt, len(verts), len(faces), count_type, index_type)
body = b"".join(struct.pack(order + "3f", *v) for v in verts)
body += b"".join(struct.pack(order + codes[count_type], len(face)) + struct.pack(order + "%d%s" % (len(face), codes[index_type]), *face)
                 for face in faces)
open(path, "wb").write(header.encode() + body)
PY
}
ply_to_obj() {  # binary PLY frame (as surfcap-synth writes them) → the same mesh as OBJ beside it
  py "$1" << 'PY'
import struct, sys
raw = open(sys.argv[1], "rb").read()
end = raw.index(b"end_header\n") + len(b"end_header\n")
lines = raw[:end].decode().split("\n")
nv = int([l for l in lines if l.startswith("element vertex")][0].split()[2])
nf = int([l for l in lines if l.startswith("element face")][0].split()[2])
props = [l for l in lines if l.startswith("property") and "list" not in l]
vsize = sum(4 if l.split()[1] in ("float", "int") else 1 for l in props)
with open(sys.argv[1][:-4] + ".obj", "w") as out:
    for v in range(nv):
        out.write("v %r %r %r\n" % struct.unpack("<3f", raw[end + v * vsize:end + v * vsize + 12]))
    p = end + nv * vsize
    for _ in range(nf):
        out.write("f %d %d %d\n" % tuple(i + 1 for i in struct.unpack("<3i", raw[p + 1:p + 13])))
        p += 13
PY
}
escaped_anywhere() {  # fails if a file named NAME appeared anywhere under $work outside the case
  if [[ -n $(find "$work" -path "$case" -prune -o -name "$1" -print) ]] || [[ -e /tmp/$1 ]]; then
    echo "FAIL [$label]: '$1' was written outside the output folder"; exit 1
  fi
}

echo "1. crashes: deep JSON, out-of-range indices"
fresh "capture.json: sequences nested 10^6 deep"; nest_field "$case/capture/capture.json" '["sequences"]'
expect 3 "capture.json'" "nested deeper than" -- histograms; count 1
fresh "cameras.json: a camera nested 10^6 deep"; nest_field "$case/capture/cameras.json" '["cameras"][0]["K"]'
expect 3 "cameras.json'" "nested deeper than" -- histograms; count 1
fresh "database.json: provenance nested 10^6 deep"; nest_field "$(db)/database.json" '["provenance"]'
expect 3 "database.json'" "nested deeper than" -- learn; count 1
fresh "graph.json: provenance nested 10^6 deep"; nest_field "$case/built/graph.json" '["provenance"]'
expect 3 "graph.json'" "nested deeper than" -- export_glb; count 1
fresh ".glb JSON chunk: extras nested 10^6 deep"; glb_json "$case/character.glb" 'j["extras"] = "@DEEP@"'
expect 3 "character.glb'" "nested deeper than" -- play; count 1
fresh ".glb JSON chunk: the extension nested 10^6 deep"
glb_json "$case/character.glb" 'j["extensions"]["SURFCAP_motion_graph"]["provenance"] = "@DEEP@"'
expect 3 "character.glb'" "nested deeper than" -- play; count 1
fresh "control script nested 10^6 deep"; nest_field "$case/control.json" '["start"]["parameters"]'
expect 3 "control.json'" "nested deeper than" -- play; count 1
fresh "edit file nested 10^6 deep"; nest_field "$case/edit.json" '["handles"]'
expect 3 "edit.json'" "nested deeper than" -- edit; count 1
fresh "parts.json nested 10^6 deep"; nest_field "$case/model/parts.json" '["examples"]'
expect 3 "parts.json'" "nested deeper than" -- edit; count 1
fresh "--config file nested 10^6 deep"; deep > "$case/config.json"
expect 2 "--config" "nested deeper than" -- histograms --config "$case/config.json"; count 1
fresh "graph config: parameter measure vertex 10^9"
json_set "$case/graph.json" 'd["spaces"][1]["parameters"][0].update(measure="hand_height", vertices=[1000000000])'
expect 3 "graph.json'" "vertex 1000000000" -- spaces; count 1
fresh "graph config: parameter measure vertex -1"
json_set "$case/graph.json" 'd["spaces"][1]["parameters"][0].update(measure="hand_height", vertices=[-1])'
expect 3 "graph.json'" "vertex index" -- spaces; count 1
fresh "graph config: parameter measure vertex 2.5"
json_set "$case/graph.json" 'd["spaces"][1]["parameters"][0].update(measure="hand_height", vertices=[2.5])'
expect 3 "graph.json'" "vertex index" -- spaces; count 1

echo "2. hangs: FIFOs, devices, huge coordinates"
fresh "frame that is a FIFO"; rm "$case/capture/walk/mesh/000004.ply"; mkfifo "$case/capture/walk/mesh/000004.ply"
expect 3 "walk/mesh/000004.ply' (frame 4)" "FIFO" -- histograms; count 2
fresh "camera image that is a FIFO"
json_set "$case/capture/capture.json" 'd["sequences"][0]["images"] = "walk/images/{camera}/{frame:06d}.png"'
read -r cam first < <(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['cameras'][0]['name'],
      json.load(open(sys.argv[2]))['sequences'][0].get('first', 0))" "$case/capture/cameras.json" "$case/capture/capture.json")
image=$case/capture/walk/images/$cam/$(printf %06d "$first").png
mkdir -p "$(dirname "$image")"; mkfifo "$image"
expect 3 "$(printf %06d "$first").png' (frame $first)" "FIFO" -- histograms; count 2
fresh "frame with coordinates ~1e30"; ply_scale "$case/capture/walk/mesh/000003.ply" 1e30
expect 3 "walk/mesh/000003.ply' (frame 3)" "plausible magnitude" -- histograms; count 2
fresh "frame that is /dev/zero"; ln -sf /dev/zero "$case/capture/run/mesh/000002.ply"
expect 3 "run/mesh/000002.ply' (frame 2)" "character device" -- histograms; count 2
fresh "positions .npy that is /dev/urandom"; ln -sf /dev/urandom "$(db)/sequences/walk.npy"
expect 3 "sequences/walk.npy'" "character device" -- learn; count 2
fresh "character .glb that is /dev/zero"; ln -sf /dev/zero "$case/character.glb"
expect 3 "character.glb'" "character device" -- play; count 2
fresh "template that is a FIFO"; rm "$(db)/template.ply"; mkfifo "$(db)/template.ply"
expect 3 "template.ply'" "FIFO" -- learn; count 2
fresh "control script that is a FIFO"; rm "$case/control.json"; mkfifo "$case/control.json"
expect 3 "control.json'" "FIFO" -- play; count 2
fresh "capture.json that is a directory"; rm "$case/capture/capture.json"; mkdir "$case/capture/capture.json"
expect 3 "capture.json'" "directory" -- histograms; count 2

echo "3. runaway memory: requests beyond the budget are refused up front"
fresh "control script: duration 4e7 s"; json_set "$case/control.json" 'd["duration_s"] = 4e7'
expect 3 "control.json'" "duration_s" -- play; count 3
fresh "control script: 10^9 fps"; json_set "$case/control.json" 'd["fps"] = 1e9'
expect 3 "control.json'" "fps" -- play; count 3
fresh "control script: a day at 1000 fps beyond --max-memory"
json_set "$case/control.json" 'd.update(duration_s=86400, fps=1000)'
expect 3 "control.json'" "86400000 frames" "--max-memory" -- play --max-memory 4G; count 3
fresh "graph config: a space of 10^9 normalised frames"; json_set "$case/graph.json" 'd["spaces"][1]["frames"] = 10**9'
expect 3 "graph.json'" "frames" -- spaces; count 3
fresh "graph config: 5·10^6 frames beyond the budget"; json_set "$case/graph.json" 'd["spaces"][1]["frames"] = 5000000'
expect 3 "graph.json'" "5000000 normalised frames" "memory budget" -- spaces; count 3
fresh "database claims 10^7 frames beyond --max-memory"; json_set "$(db)/database.json" 'd["sequences"][0]["frames"] = 10**7'
expect 3 "database.json'" "10000000 frames" "--max-memory" -- learn --max-memory 1G; count 3
fresh "camera of 65536×65536 beyond --max-memory"
json_set "$case/capture/cameras.json" 'd["cameras"][0].update(width=65536, height=65536)'
expect 3 "capture.json'" "65536×65536" "--max-memory" -- histograms --max-memory 8G; count 3
fresh "a 64 MB capture.json beyond --max-memory 16M"
py "$case/capture/capture.json" << 'PY'
import json, sys
d = json.load(open(sys.argv[1])); d["padding"] = "x" * (64 << 20); json.dump(d, open(sys.argv[1], "w"))
PY
expect 3 "capture.json'" "memory budget" -- histograms --max-memory 16M; count 3
fresh "--max-memory that is not a size"; expect 2 "--max-memory" -- histograms --max-memory lots
count 3

echo "4. reads and writes outside the folders"
fresh "frame pattern ../../x/{frame:06d}.ply"
mkdir -p "$case/x"; cp "$case"/capture/walk/mesh/*.ply "$case/x/"
json_set "$case/capture/capture.json" 'd["sequences"][0]["frames"] = "../../x/{frame:06d}.ply"'
expect 3 "capture.json'" '"frames"' "leaves the folder" -- histograms; count 4
fresh "frame pattern that is an absolute path"
json_set "$case/capture/capture.json" "d['sequences'][0]['frames'] = '$case/capture/walk/mesh/{frame:06d}.ply'"
expect 3 "capture.json'" '"frames"' "absolute" -- histograms; count 4
fresh "cameras: /etc/passwd"; json_set "$case/capture/capture.json" 'd["cameras"] = "/etc/passwd"'
expect 3 "capture.json'" '"cameras"' -- histograms
if grep -q "root:" "$work/stderr"; then echo "FAIL [$label]: /etc/passwd echoed"; exit 1; fi
count 4
fresh "database positions ../x.npy"; cp "$(db)/sequences/walk.npy" "$case/capture/ground_truth/walk.npy"
json_set "$(db)/database.json" 'd["sequences"][0]["positions"] = "../walk.npy"'
expect 3 "database.json'" '"positions"' -- learn; count 4
fresh "parts model vertex file ../x.npy"; cp "$case/model/parts/head.vertices.npy" "$case/head.vertices.npy"
json_set "$case/model/parts.json" 'd["parts"][1]["vertices"] = "../head.vertices.npy"'
expect 3 "parts.json'" '"vertices"' -- edit; count 4
fresh "space named ../../escaped_space"; json_set "$case/graph.json" 'd["spaces"][1]["name"] = "../../escaped_space"'
expect 3 "graph.json'" '"name"' -- spaces; escaped_anywhere escaped_space; count 4
fresh "space named by an absolute path"; json_set "$case/graph.json" "d['spaces'][1]['name'] = '$work/abs_space'"
expect 3 "graph.json'" '"name"' -- spaces; escaped_anywhere abs_space; count 4
fresh ".glb image URI file:///etc/shadow"
glb_json "$case/character.glb" 'j.setdefault("images", []).append({"uri": "file:///etc/shadow"})'
expect 3 "character.glb'" "external URI" -- play; count 4
fresh "image pattern ../../x/{camera}/{frame:06d}.png"
json_set "$case/capture/capture.json" 'd["sequences"][0]["images"] = "../../x/{camera}/{frame:06d}.png"'
expect 3 "capture.json'" '"images"' "leaves the folder" -- histograms; count 4
fresh "database template /etc/passwd"; json_set "$(db)/database.json" 'd["template"] = "/etc/passwd"'
expect 3 "database.json'" '"template"' -- learn; count 4
fresh "graph.json space references ../../x"
json_set "$case/built/graph.json" 'd["spaces"][0]["references"] = "../../x/references.npy"'
expect 3 "graph.json'" '"references"' -- export_glb; count 4
fresh "capture sequence named ../walk"; json_set "$case/capture/capture.json" 'd["sequences"][0]["name"] = "../walk"'
expect 3 "capture.json'" '"name"' -- histograms; count 4
fresh "part config: a part named ../../escaped_part"
json_set "$case/part_config.json" 'd["parts"][1]["name"] = "../../escaped_part"; d["parts"][1]["vertices"] = [0, 1, 2]'
expect 3 "part_config.json'" '"name"' -- learn; escaped_anywhere 'escaped_part*'; count 4
fresh "graph.json transition to ../../x"; json_set "$case/built/graph.json" 'd["transitions"][0]["to"] = "../../x"'
expect 3 "graph.json'" '"to"' -- export_glb; count 4
fresh "opt-in: --allow-outside-paths reads an absolute frame pattern"
json_set "$case/capture/capture.json" "d['sequences'][0]['frames'] = '$case/capture/walk/mesh/{frame:06d}.ply'"
expect 0 -- histograms --allow-outside-paths; count 4

echo "5. bad input that was accepted"
fresh "first 1, count 2147483647"; json_set "$case/capture/capture.json" 'd["sequences"][0].update(first=1, count=2147483647)'
expect 3 "capture.json'" '"count"' -- histograms; count 5
fresh "singular camera matrix K"; json_set "$case/capture/cameras.json" 'd["cameras"][0]["K"][8] = 0'
expect 3 "cameras.json'" "K" -- histograms; count 5
fresh "database fps -25"; json_set "$(db)/database.json" 'd["fps"] = -25'
expect 3 "database.json'" '"fps"' -- learn; count 5
fresh "root frame 100000 of a 24-frame sequence"; json_set "$(db)/database.json" 'd["root"] = {"sequence": "walk", "frame": 100000}'
expect 3 "database.json'" "root frame 100000" -- learn; count 5
fresh "parameter-map degree 1000"; json_set "$case/graph.json" 'd["spaces"][1]["degree"] = 1000'
expect 3 "graph.json'" '"degree"' -- spaces; count 5
fresh "edit translating by 1e308 m"; json_set "$case/edit.json" 'd["handles"][0]["translate"] = [1e308, 0, 0]'
expect 3 "edit.json'" "translate" -- edit; count 5
test ! -e "$case/out/edited.ply"
fresh "capture fps -25"; json_set "$case/capture/capture.json" 'd["fps"] = -25'
expect 3 "capture.json'" '"fps"' -- histograms; count 5
fresh "camera focal length 0"; json_set "$case/capture/cameras.json" 'd["cameras"][0]["K"][0] = 0'
expect 3 "cameras.json'" "focal" -- histograms; count 5
fresh "camera 10^6 pixels wide"; json_set "$case/capture/cameras.json" 'd["cameras"][0]["width"] = 1000000'
expect 3 "cameras.json'" "image size" -- histograms; count 5
fresh "root motion 1e30 m"; npy_scale "$(db)/sequences/run.root.npy" 1e30
expect 3 "run.root.npy'" "plausible magnitude" -- learn; count 5
fresh "control waypoint at x = 1e300"; json_set "$case/control.json" 'd["waypoints"] = [{"x": 1e300, "z": 0}]'
expect 3 "control.json'" '"x"' -- play; count 5
fresh "graph config tolerance -5 mm"; json_set "$case/graph.json" 'd["spaces"][1]["tolerance_mm"] = -5'
expect 3 "graph.json'" '"tolerance_mm"' -- spaces; count 5
fresh "parts.json: an example at frame 1.5"; json_set "$case/model/parts.json" 'd["examples"][0]["frame"] = 1.5'
expect 3 "parts.json'" '"frame"' -- edit; count 5

echo "6. bad input reported as an internal error or without its file"
fresh "database: frames -1"; json_set "$(db)/database.json" 'd["sequences"][0]["frames"] = -1'
expect 3 "database.json'" '"frames"' -- learn; count 6
fresh "export: database fps 0"; json_set "$(db)/database.json" 'd["fps"] = 0'
expect 3 "database.json'" '"fps"' -- export_glb; count 6
fresh "play --preview-frames -1"; expect 2 "--preview-frames" -- play --preview-frames -1
test ! -e "$case/out/animation.glb"; count 6
fresh "edit file: translate of strings"; json_set "$case/edit.json" 'd["handles"][0]["translate"] = ["a", 0, 0]'
expect 3 "edit.json'" "translate" -- edit; count 6
fresh "edit file: region of the wrong type"; json_set "$case/edit.json" 'd["handles"][0]["region"] = 5'
expect 3 "edit.json'" '"region"' -- edit; count 6
fresh "parts.json: parts is a number"; json_set "$case/model/parts.json" 'd["parts"] = 5'
expect 3 "parts.json'" -- edit; count 6
fresh "control script: start is a number"; json_set "$case/control.json" 'd["start"] = 3'
expect 3 "control.json'" -- play; count 6
fresh "control script: planner depth as text"; json_set "$case/control.json" 'd["planner"] = {"depth": "deep"}'
expect 3 "control.json'" '"depth"' -- play; count 6
fresh "graph config: spaces is an object"; json_set "$case/graph.json" 'd["spaces"] = {"a": 1}'
expect 3 "graph.json'" -- spaces; count 6
fresh "capture: count as text"; json_set "$case/capture/capture.json" 'd["sequences"][0]["count"] = "24"'
expect 3 "capture.json'" '"count"' -- histograms; count 6

echo "7. valid input that was refused"
for ply in "binary_little_endian ushort int" "binary_little_endian uint int" "binary_big_endian ushort int" \
           "binary_little_endian ushort uint"; do
  fresh "PLY with 300-vertex polygons, list $ply"; prism "$case/capture/walk/mesh/000005.ply" $ply
  expect 0 -- histograms; count 7
done
fresh "OBJ with 300-vertex polygons"
for f in "$case"/capture/walk/mesh/*.ply; do ply_to_obj "$f"; done
prism "$case/capture/walk/mesh/000005.obj" obj
json_set "$case/capture/capture.json" 'd["sequences"][0]["frames"] = "walk/mesh/{frame:06d}.obj"'
expect 0 -- histograms; count 7

total=0
for class in 1 2 3 4 5 6 7; do
  echo "class $class: ${per_class[$class]:-0} cases"
  total=$((total + ${per_class[$class]:-0}))
done
echo "hostile_inputs: $tried cases ($total counted by class): ok"
