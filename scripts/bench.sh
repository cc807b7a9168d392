#!/usr/bin/env bash
# Builds and runs tests/benchmarks (Google Benchmark): build/bench/results.json + results.md.
# Usage: scripts/bench.sh [--benchmark_filter=REGEX] [other Google Benchmark flags]
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh --benchmarks
mkdir -p build/bench
./build/tests/benchmarks/surfcap_bench --benchmark_repetitions="${SURFCAP_BENCH_REPETITIONS:-5}" \
  --benchmark_report_aggregates_only=true --benchmark_out=build/bench/results.json \
  --benchmark_out_format=json "$@"
python3 scripts/bench_table.py build/bench/results.json > build/bench/results.md
echo "bench: build/bench/results.json and build/bench/results.md"
cat build/bench/results.md
