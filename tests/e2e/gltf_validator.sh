#!/usr/bin/env bash
# The Khronos glTF-Validator (npm gltf-validator, run through Node) on what surfcap writes:
# character.glb exported by surfcap-export from the synthetic tiny build in both forms
# (compressed and --uncompressed), animation.glb of surfcap-play in both forms (or of
# asset::write_animation_glb, the seed in tests/fuzz/corpus/glb, when surfcap-play is not
# built), and the reader's seed files. Every file must have 0 errors and 0 warnings.
# The validator is installed into <build>/cache/gltf-validator on first use.
# Usage: bash gltf_validator.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
validator_version=2.0.0-dev.3.10
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "SKIP: node and npm are needed to run the Khronos glTF-Validator (apt-get install nodejs npm)"
  exit 77
fi
cache=$build/cache/gltf-validator
if [[ ! -f $cache/node_modules/gltf-validator/package.json ]] ||
   ! grep -q "\"version\": \"$validator_version\"" "$cache/node_modules/gltf-validator/package.json"; then
  mkdir -p "$cache"
  (cd "$cache" && npm install --no-audit --no-fund --loglevel=error "gltf-validator@$validator_version")
fi
validate() { node "$source/tests/e2e/gltf_validate.js" "$cache" "$@"; }

files=("$source"/tests/fuzz/corpus/glb/character.glb "$source"/tests/fuzz/corpus/glb/character_float_colours.glb)
work=$(mktemp -d "$build/gltf_validator_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
export_tool=$build/tools/surfcap-export
if [[ -x $export_tool ]]; then
  "$build/tools/surfcap-synth" --preset tiny --no-images --out "$work/capture" --threads 2 > "$work/synth.log" 2>&1
  database=$work/capture/ground_truth/database/database.json
  graph_config=$source/configs/graphs/tiny.json
  precompute=$build/tools/surfcap-precompute
  "$precompute" --threads 2 spaces --database "$database" --graph "$graph_config" --output "$work/out" \
    --sweep-mm 5 --validation-samples 2 > "$work/spaces.log" 2>&1
  "$precompute" --threads 2 transitions --database "$database" --graph "$graph_config" --output "$work/out" \
    > "$work/transitions.log" 2>&1
  "$export_tool" --database "$database" --graph "$work/out/graph.json" --output "$work/character.glb" \
    --report "$work/export.json"
  test -s "$work/character.png"
  python3 - "$work/export.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
assert report["round_trip_identical"], "character.glb does not read back to the same bytes"
content = report["content"]
print("export:", content["file_bytes"], "bytes,", content["morph_targets"], "morph targets,",
      len(content["spaces"]), "spaces,", len(content.get("transitions", [])), "transitions,",
      "%.3f s" % report["timings_s"]["write"])
PY
  "$export_tool" --database "$database" --graph "$work/out/graph.json" --output "$work/character_plain.glb" \
    --report "$work/export_plain.json" --uncompressed
  python3 - "$work/export.json" "$work/export_plain.json" <<'PY'
import json, sys
small, large = (json.load(open(path)) for path in sys.argv[1:])
assert small["content"]["compressed"] and not large["content"]["compressed"]
assert large["round_trip_identical"], "the uncompressed form does not read back to the same bytes"
ratio = large["content"]["file_bytes"] / small["content"]["file_bytes"]
print(f"compressed {small['content']['file_bytes']} bytes, uncompressed {large['content']['file_bytes']} bytes: {ratio:.2f}x")
assert ratio > 2, "the compressed form is not smaller"
PY
  files+=("$work/character.glb" "$work/character_plain.glb")
  # The same command gives the same bytes (the options, output path included, are the provenance).
  cp "$work/character.glb" "$work/first.glb"
  "$export_tool" --database "$database" --graph "$work/out/graph.json" --output "$work/character.glb" \
    --report "$work/export.json" > /dev/null 2>&1
  cmp "$work/character.glb" "$work/first.glb"
  # Documented exit codes.
  set +e
  "$export_tool" --database "$database" --graph "$work/out/graph.json" --output "$work/character.txt" 2> /dev/null
  [[ $? -eq 2 ]] || { echo "an --output that is not .glb must exit 2"; exit 1; }
  "$export_tool" --database "$work/missing.json" --graph "$work/out/graph.json" --output "$work/x.glb" 2> /dev/null
  [[ $? -eq 4 ]] || { echo "a missing database must exit 4"; exit 1; }
  head -c 1000 "$work/character.glb" > "$work/truncated.glb"
  "$build/tools/surfcap-play" --character "$work/truncated.glb" --script "$source/configs/control/tiny_timeline.json" \
    --output "$work/bad" 2> "$work/err"
  [[ $? -eq 3 ]] && grep -q "truncated.glb" "$work/err" || { echo "a truncated character must exit 3 naming it"; exit 1; }
  set -e
  play=$build/tools/surfcap-play
  if [[ -x $play ]]; then
    if "$play" --threads 2 --character "$work/character.glb" --script "$source/configs/control/tiny_timeline.json" --output "$work/play" > "$work/play.log" 2>&1; then
      "$play" --threads 2 --character "$work/character.glb" --script "$source/configs/control/tiny_timeline.json" \
        --output "$work/play_plain" --uncompressed > "$work/play_plain.log" 2>&1
      cp "$work/play_plain/animation.glb" "$work/animation_plain.glb"
      files+=("$work/play/animation.glb" "$work/animation_plain.glb")
    else
      echo "surfcap-play failed:"; tail -5 "$work/play.log"; exit 1
    fi
  else
    files+=("$source/tests/fuzz/corpus/glb/animation.glb")
  fi
else
  echo "note: surfcap-export is not built; validating the writer's seed files only"
  files+=("$source/tests/fuzz/corpus/glb/animation.glb")
fi
validate "${files[@]}"
echo "gltf_validator: ok"
