#!/usr/bin/env bash
# Installs the three.js npm package the run report's viewer inlines (pipelines/report.py) into
# DIR/node_modules/three, unless that version is there already. Needs npm (Debian: npm) and the
# npm registry; without them, says so and exits 0: the report is then written without its viewer.
# Usage: scripts/vendor_three.sh DIR
set -euo pipefail
dir=${1:?usage: vendor_three.sh DIR}
version=0.187.0
if [[ -f $dir/node_modules/three/package.json ]] &&
   grep -q "\"version\": \"$version\"" "$dir/node_modules/three/package.json"; then
  exit 0
fi
if ! command -v npm > /dev/null 2>&1; then
  echo "vendor_three: npm is missing (apt-get install npm): the report will have no 3D viewer" >&2
  exit 0
fi
mkdir -p "$dir"
(cd "$dir" && npm install --no-audit --no-fund --loglevel=error --no-save "three@$version" > /dev/null) ||
  echo "vendor_three: npm install three@$version failed: the report will have no 3D viewer" >&2
