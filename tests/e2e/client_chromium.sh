#!/usr/bin/env bash
# A real browser on the run report: pipelines/character.mk (tiny capture, ground-truth database)
# writes OUT/report/index.html; headless Chromium (Debian's chromium, installed here when
# missing) loads it with the network off and a fresh profile. The page's three.js viewer must
# load character.glb (compressed: KHR_mesh_quantization + EXT_meshopt_compression) with as many
# morph targets and animations as surfcap-export wrote, and animation.glb with one morph target
# per played frame; both with normals (smooth shading); frames must be rendered and the morph
# weights must change; a screenshot is taken. Skips (77) only when Chromium cannot be installed.
# Usage: bash client_chromium.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
# shellcheck source=pipeline_lib.bash
. "$source/tests/e2e/pipeline_lib.bash"
# shellcheck source=support/common.bash
. "$source/tests/e2e/support/common.bash"
pipeline_require_tools
[[ $(pipeline_targets) == *previews* ]] || { echo "SKIP: surfcap-export / surfcap-play are not built"; exit 77; }
install_packages chromium || { echo "SKIP: chromium cannot be installed (apt-get install chromium)"; exit 77; }
command -v npm > /dev/null 2>&1 || install_packages npm || { echo "SKIP: npm cannot be installed"; exit 77; }
work=$(mktemp -d "$build/client_chromium.XXXXXX")
trap 'rm -rf "$work"' EXIT

"$build/tools/surfcap-synth" --preset tiny --seed 1 --no-images --out "$work/capture" --log-level warn
start=$(date +%s)
pipeline_make "$work/run" DATABASE=truth BLOCKS=1 THREADS=2 SPACES_OPTIONS="--sweep-mm 5 --validation-samples 2" \
  THREE="$build/cache/three" -j2 character previews report > "$work/make.log" || { tail -20 "$work/make.log"; exit 1; }
echo "pipeline + report: $(( $(date +%s) - start )) s"
page=$work/run/out/report/index.html
test -s "$page"
grep -q "Content-Security-Policy" "$page"
! grep -qE "(src|href)=\"(https?:)?//" "$page" || { echo "index.html refers to the network"; exit 1; }

chrome=(chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
        --disable-component-update --disable-sync --enable-unsafe-swiftshader --window-size=1200,1600)
# How many frames software WebGL renders within a virtual-time budget depends on the machine's
# load (4 to 20 in 15 s measured on a loaded 2-core machine), so the page is loaded again with a
# longer budget while it has not yet rendered two frames with changing morph weights.
for budget in 15000 60000 180000; do
  timeout 300 "${chrome[@]}" --virtual-time-budget=$budget --user-data-dir="$work/profile-dom-$budget" \
    --dump-dom "file://$page" > "$work/dom.html" 2>> "$work/chromium.log"
  python3 - "$work/dom.html" <<'PY' && break
import html, json, re, sys
match = re.search(r'<pre id="viewer-status">(.*?)</pre>', open(sys.argv[1], encoding="utf-8").read(), re.S)
status = json.loads(html.unescape(match.group(1))) if match else {}
print("viewer status:", {k: status.get(k) for k in ("framesRendered", "morphTargetsChanged", "errors")})
sys.exit(0 if status.get("framesRendered", 0) >= 2 and status.get("morphTargetsChanged") else 1)
PY
  echo "virtual-time budget $budget ms: the viewer had not played two frames yet; loading again"
done
timeout 300 "${chrome[@]}" --virtual-time-budget=15000 --user-data-dir="$work/profile-shot" \
  --screenshot="$work/screenshot.png" "file://$page" >> "$work/chromium.log" 2>&1
python3 - "$work/dom.html" "$work/run/out/report/export.json" "$work/run/out/previews/report.json" "$work/screenshot.png" <<'PY'
import html, json, os, re, sys
dom, export, play, screenshot = sys.argv[1:]
match = re.search(r'<pre id="viewer-status">(.*?)</pre>', open(dom, encoding="utf-8").read(), re.S)
assert match, "no viewer status in the page"
status = json.loads(html.unescape(match.group(1)))
print("viewer:", json.dumps(status))
content = json.load(open(export))["content"]
frames, fps = json.load(open(play))["frames"], json.load(open(play))["fps"]
assert not status["errors"], status["errors"]
assert status["webgl"], "no WebGL context"
files = {entry["file"]: entry for entry in status["loaded"]}
character, animation = files["character.glb"], files["animation.glb"]
assert content["compressed"], "the pipeline's character.glb is not the compressed form"
assert character["morphTargets"] == content["morph_targets"], (character, content["morph_targets"])
assert character["animations"] == content["animations"], (character, content["animations"])
assert animation["morphTargets"] == frames and animation["animations"] == 1, (animation, frames)
for entry in (character, animation):
    assert entry["normals"] and not entry["flatShading"], f"{entry['file']} is shaded flat"
    assert entry["vertexColors"], f"{entry['file']} has no vertex colours"
    assert entry["fps"] == fps, f"{entry['file']}: scene extras fps {entry['fps']}, capture {fps}"
assert status["framesRendered"] >= 2, "the viewer did not advance"
assert status["morphTargetsChanged"], "the morph weights did not change while playing"
assert os.path.getsize(screenshot) > 20000, "screenshot missing or blank"
print(f"client_chromium: ok ({os.path.getsize(screenshot)} byte screenshot)")
PY
if [[ -n ${SURFCAP_KEEP_SCREENSHOT:-} ]]; then cp "$work/screenshot.png" "$SURFCAP_KEEP_SCREENSHOT"; fi
