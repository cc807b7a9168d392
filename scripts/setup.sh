#!/usr/bin/env bash
# Installs the Debian packages surfcap needs (only those missing) and builds Release into build/.
# Usage: scripts/setup.sh [--benchmarks] [--sanitize] [--build-dir DIR] [--deps-only] [--target=NAME ...]
#   --target=NAME  build only these targets (e.g. the executables demo.sh runs); default all
# Environment: SURFCAP_JOBS (default: nproc).
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
cmake_options=()
build=1
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --benchmarks) cmake_options+=(-DSURFCAP_BUILD_BENCHMARKS=ON) ;;
    --sanitize)
      # -O1 with line tables: full stack traces at a fraction of the compile time. clang when
      # present: it builds this tree ~3x faster than GCC (hybrid_blend.cpp: 5 s vs 18 s CPU).
      cmake_options+=(-DSURFCAP_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo)
      if command -v clang++ > /dev/null 2>&1; then
        cmake_options+=(-DCMAKE_CXX_COMPILER=clang++ "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG")
      else
        cmake_options+=("-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG")
      fi
      ;;
    --build-dir) build_dir="$2"; shift ;;
    --deps-only) build=0 ;;
    --target=*) targets+=("${1#--target=}") ;;
    *) echo "setup.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

packages=(
  build-essential cmake pkg-config git
  libeigen3-dev libopenmesh-dev libopencv-dev libflann-dev libcgal-dev libtet1.5-dev
  libcli11-dev libspdlog-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev
  libtinygltf-dev libmeshoptimizer-dev libsuitesparse-dev libtbb-dev strace
)
missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} packages present"
fi

[ "$build" -eq 1 ] || exit 0
jobs=${SURFCAP_JOBS:-$(nproc)}
# ccache, when present, makes rebuilds (and builds of other checkouts of the tree) cheap.
if command -v ccache >/dev/null 2>&1; then cmake_options+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSURFCAP_MODULES= "${cmake_options[@]}" > "$build_dir.configure.log" 2>&1 \
  || { cat "$build_dir.configure.log"; exit 1; }
rm -f "$build_dir.configure.log"
echo "setup: building into $build_dir/ with $jobs jobs"
cmake --build "$build_dir" -j "$jobs" ${targets[@]:+--target "${targets[@]}"}
