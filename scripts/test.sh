#!/usr/bin/env bash
# Set-up (packages + Release build), then every test.
# Usage: scripts/test.sh [--sanitize] [ctest arguments...]
#   --sanitize  build into build-asan/ with ASan+UBSan and run the tests there (docs/reliability.md)
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
setup_options=()
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-asan
  setup_options=(--sanitize --build-dir build-asan)
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  # The fault-injection e2e tests run each stage several times; one kill per stage is enough here.
  export SURFCAP_KILLS=${SURFCAP_KILLS:-1}
  shift
fi
./scripts/setup.sh "${setup_options[@]}"
cd "$build_dir"
ctest --output-on-failure -j "${SURFCAP_TEST_JOBS:-2}" "$@"
