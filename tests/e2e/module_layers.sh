#!/usr/bin/env bash
# The library's layering is enforced: cmake/CheckModuleLayers.cmake (run on every module when its
# files change) accepts the modules as they are and rejects an include from a higher module.
set -euo pipefail
source=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/module_layers.XXXXXX")
trap 'rm -rf "$work"' EXIT
check() {  # module allowed-modules directory
  cmake -DMODULE="$1" -DALLOWED="$2" -DDIRECTORY="$3" -DSTAMP="$work/stamp" -P "$source/cmake/CheckModuleLayers.cmake"
}
check align align,core,geometry,render,similarity "$source/lib/surfcap/align" > /dev/null
check core core "$source/lib/surfcap/core" > /dev/null
mkdir -p "$work/geometry"
printf '#include "surfcap/core/mesh.hpp"\n#include "surfcap/align/tree_alignment.hpp"\n' > "$work/geometry/upward.cpp"
if check geometry geometry,core "$work/geometry" > "$work/log" 2>&1; then
  echo "an upward include was accepted"; exit 1
fi
grep -q "geometry/upward.cpp includes surfcap/align/" "$work/log" || { cat "$work/log"; exit 1; }
echo "module layers ok"
