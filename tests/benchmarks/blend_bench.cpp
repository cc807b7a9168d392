// Placeholder replaced below.
#include <benchmark/benchmark.h>
static void BM_blend_placeholder(benchmark::State& state) { for (auto _ : state) benchmark::DoNotOptimize(1); }
BENCHMARK(BM_blend_placeholder);
