#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan+UBSan; only the modules the readers need) into
# build-fuzz/ and runs each, one after the other, for a bounded time from the seed corpus in
# tests/fuzz/corpus/<target>/.
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET (default 60)] [TARGET...]
# Environment: SURFCAP_FUZZ_RUNS=N also stops each target after N executions; SURFCAP_FUZZ_JOBS=N
# runs N targets side by side.
# Findings (crashing inputs) land in build-fuzz/findings/<target>/; the summary in
# build-fuzz/fuzz-summary.txt lists executions and findings per target.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
./scripts/setup.sh --deps-only
missing=()
for package in clang libclang-rt-14-dev; do
  [ "$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)" = "install ok installed" ] || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DSURFCAP_FUZZ=ON \
  -DSURFCAP_MODULES="core;geometry;blend;graph;learn;asset;runtime;render" -DSURFCAP_BUILD_TOOLS=OFF -DSURFCAP_BUILD_TESTS=OFF > build-fuzz.configure.log 2>&1 \
  || { cat build-fuzz.configure.log; exit 1; }
rm -f build-fuzz.configure.log
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=($(ls tests/fuzz/*_fuzz.cpp | xargs -n1 basename | sed 's/_fuzz.cpp//'))
fi
cmake --build build-fuzz -j "${SURFCAP_JOBS:-$(nproc)}" --target $(printf 'fuzz_%s ' "${targets[@]}")
summary=build-fuzz/fuzz-summary.txt
rm -rf build-fuzz/findings build-fuzz/status  # each run reports its own findings; fixed ones live on as seeds in tests/fuzz/corpus
mkdir -p build-fuzz/status

run_target() {
  local target=$1 work=build-fuzz/corpus/$1 findings=build-fuzz/findings/$1 log=build-fuzz/$1.log rc runs found
  mkdir -p "$work" "$findings"
  cp -n tests/fuzz/corpus/"$target"/* "$work"/ 2>/dev/null || true
  set +e
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
    ./build-fuzz/tests/fuzz/fuzz_"$target" -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 \
    -timeout=10 ${SURFCAP_FUZZ_RUNS:+-runs=$SURFCAP_FUZZ_RUNS} -print_final_stats=1 -artifact_prefix="$findings/" "$work" > "$log" 2>&1
  rc=$?
  set -e
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  found=$(ls "$findings" | wc -l)
  echo "$target: $runs executions (at most ${seconds} s), $found findings (exit $rc)" > build-fuzz/status/"$target"
  [ "$rc" -eq 0 ] && [ "$found" -eq 0 ] || touch build-fuzz/status/"$target".failed
}

# SURFCAP_FUZZ_JOBS targets run side by side (default 1: one after the other).
jobs=${SURFCAP_FUZZ_JOBS:-1}
for target in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  run_target "$target" &
done
wait
status=0
: > "$summary"
for target in "${targets[@]}"; do
  tee -a "$summary" < build-fuzz/status/"$target"
  [ ! -e build-fuzz/status/"$target".failed ] || status=1
done
exit $status
