#!/usr/bin/env bash
# A real digital-content-creation client on what surfcap writes: Debian's Blender (installed here
# with python3-numpy when missing; its glTF importer needs the one-line numpy workaround in
# support/blender_import.py) imports character.glb and animation.glb of the synthetic tiny build,
# written with --uncompressed (Blender 3.4 does not read EXT_meshopt_compression). Blender must
# see the template's vertices, every polygon smooth-shaded (normals are in the file), one shape
# key per morph target, the animations as actions, the capture's frame rate from the scene extras,
# vertex 0 in the captured colour, vertices moving between frames and, in animation.glb, the
# object itself moving (root motion on the node). Skips (77) only when Blender cannot be installed.
# Usage: bash client_blender.sh <build_dir> <source_dir>
set -euo pipefail
build=$(cd "$1" && pwd)
source=$(cd "$2" && pwd)
tools=$build/tools
# shellcheck source=support/common.bash
. "$source/tests/e2e/support/common.bash"
require_tools surfcap-synth surfcap-precompute surfcap-export surfcap-play
start=$(date +%s)
install_packages blender python3-numpy || { echo "SKIP: blender cannot be installed (apt-get install blender python3-numpy)"; exit 77; }
echo "blender present after $(( $(date +%s) - start )) s"
work=$(mktemp -d "$build/client_blender.XXXXXX")
trap 'rm -rf "$work"' EXIT

"$tools/surfcap-synth" --preset tiny --seed 1 --no-images --out "$work/capture" --log-level warn
database=$work/capture/ground_truth/database/database.json
graph=$source/configs/graphs/tiny.json
"$tools/surfcap-precompute" --threads 2 --log-level warn spaces --database "$database" --graph "$graph" \
  --output "$work/out" --sweep-mm 5 --validation-samples 2
"$tools/surfcap-precompute" --threads 2 --log-level warn transitions --database "$database" --graph "$graph" --output "$work/out"
"$tools/surfcap-export" --log-level warn --database "$database" --graph "$work/out/graph.json" \
  --output "$work/character.glb" --report "$work/export.json" --uncompressed
"$tools/surfcap-play" --log-level warn --threads 2 --character "$work/character.glb" \
  --script "$source/configs/control/tiny_timeline.json" --output "$work/play" --uncompressed

start=$(date +%s)
timeout 600 blender --background --factory-startup --python-exit-code 1 \
  --python "$source/tests/e2e/support/blender_import.py" -- "$work/blender.json" \
  "$work/character.glb" "$work/play/animation.glb" > "$work/blender.log" 2>&1 ||
  { tail -30 "$work/blender.log"; echo "Blender could not import the files"; exit 1; }
echo "blender import: $(( $(date +%s) - start )) s"
python3 - "$work/blender.json" "$work/export.json" "$work/play/report.json" \
  "$work/capture/ground_truth/database/template.ply" <<'PY'
import json, struct, sys
blender, export, play, template = sys.argv[1:]
character, animation = json.load(open(blender))
content = json.load(open(export))["content"]
played = json.load(open(play))
print("blender:", json.dumps(character), json.dumps(animation), sep="\n  ")


def ply_colour_of_vertex0(path):
    """(r, g, b) bytes of vertex 0 of a PLY file (ascii or binary little-endian)."""
    with open(path, "rb") as handle:
        header = []
        while True:
            line = handle.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        fmt = next(l.split()[1] for l in header if l.startswith("format"))
        properties, in_vertex = [], False
        for line in header:
            words = line.split()
            if words[0] == "element":
                in_vertex = words[1] == "vertex"
            elif words[0] == "property" and in_vertex:
                properties.append((words[-1], words[1]))
        if fmt == "ascii":
            values = dict(zip((n for n, _ in properties), handle.readline().split()))
            return [int(values[c]) for c in ("red", "green", "blue")]
        codes = {"float": "f", "float32": "f", "double": "d", "uchar": "B", "uint8": "B", "int": "i", "uint": "I"}
        layout = "<" + "".join(codes[t] for _, t in properties)
        values = dict(zip((n for n, _ in properties), struct.unpack(layout, handle.read(struct.calcsize(layout)))))
        return [int(values[c]) for c in ("red", "green", "blue")]


def to_srgb(c):
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055


for result in (character, animation):
    assert result["smooth_polygons"] == result["polygons"] > 0, f"{result['file']}: not smooth-shaded"
    assert result["vertices"] == content["vertices"], (result["vertices"], content["vertices"])
    assert abs(result["scene_fps"] - played["fps"]) < 1e-6, (result["scene_fps"], played["fps"])
    assert result["max_move_m"] > 1e-3, f"{result['file']}: the vertices do not move between frames"
assert character["shape_keys"] == content["morph_targets"], (character["shape_keys"], content["morph_targets"])
assert character["actions"] >= content["animations"], (character["actions"], content["animations"])
assert animation["shape_keys"] == played["frames"], (animation["shape_keys"], played["frames"])
assert animation["actions"] >= 1
assert animation["max_root_move_m"] > 0.05, "animation.glb: the object does not move (no root motion)"
expected = ply_colour_of_vertex0(template)
seen = [round(255 * to_srgb(c)) for c in character["colour_vertex0"]]  # Blender holds linear colours
assert all(abs(a - b) <= 1 for a, b in zip(seen, expected)), f"vertex 0: Blender shows {seen}, captured {expected}"
print(f"client_blender: ok (vertex 0 colour {seen}, captured {expected})")
PY
