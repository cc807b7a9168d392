// Similarity stage: histogram per frame, filtered matrix for N frames, spanning tree.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "surfcap/core/mesh.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/similarity/shape_histogram.hpp"
#include "surfcap/similarity/similarity_matrix.hpp"
#include "surfcap/similarity/spanning_tree.hpp"

namespace {

using namespace surfcap;
using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// A person-sized (0.36 × 1.7 × 0.24 m, about 0.08 m³) star-shaped body of (rings-1)·segments + 2 vertices.
core::Mesh body(int rings, int segments) {
  core::Mesh mesh;
  const int n = (rings - 1) * segments + 2;
  mesh.V.resize(n, 3);
  auto place = [&](int v, double theta, double phi) {
    const double r = 1.0 + 0.25 * std::sin(3 * phi + 0.4) * std::sin(theta) + 0.15 * std::cos(2 * theta);
    mesh.V.row(v) << 0.18 * r * std::sin(theta) * std::cos(phi), 0.85 * r * std::cos(theta),
        0.12 * r * std::sin(theta) * std::sin(phi);
  };
  place(0, 0, 0);
  place(n - 1, M_PI, 0);
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) place(1 + (r - 1) * segments + s, M_PI * r / rings, 2 * M_PI * s / segments);
  auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  std::vector<Eigen::Vector3i> faces;
  for (int s = 0; s < segments; ++s) faces.emplace_back(0, at(1, s + 1), at(1, s));
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      faces.emplace_back(at(r, s), at(r, s + 1), at(r + 1, s));
      faces.emplace_back(at(r, s + 1), at(r + 1, s + 1), at(r + 1, s));
    }
  for (int s = 0; s < segments; ++s) faces.emplace_back(n - 1, at(rings - 1, s), at(rings - 1, s + 1));
  mesh.F.resize(static_cast<long>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.F.row(static_cast<long>(f)) = faces[f].transpose();
  return mesh;
}

void BM_ShapeHistogram3k(benchmark::State& state) {
  const core::Mesh mesh = body(40, 75);  // 2,927 vertices
  similarity::ShapeHistogramOptions options;
  options.voxel_size = static_cast<double>(state.range(0)) / 1000.0;
  for (auto _ : state) benchmark::DoNotOptimize(similarity::shape_histogram(mesh, options));
  state.counters["vertices"] = static_cast<double>(mesh.vertex_count());
  state.counters["voxel_mm"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_ShapeHistogram3k)->Arg(10)->Arg(15)->Arg(20)->Unit(benchmark::kMillisecond);

RowMatrix random_histograms(long n, const similarity::ShapeHistogramOptions& layout) {
  std::mt19937 random(11);
  std::normal_distribution<float> normal;
  RowMatrix histograms(n, layout.size());
  for (long i = 0; i < histograms.size(); ++i) histograms.data()[i] = normal(random);
  return histograms;
}

void BM_SimilarityMatrix(benchmark::State& state) {
  const long n = state.range(0);
  const similarity::ShapeHistogramOptions layout;
  const RowMatrix histograms = random_histograms(n, layout);
  const similarity::FrameIndex index({static_cast<int>(n / 2), static_cast<int>(n - n / 2)});
  similarity::SimilarityOptions options;
  options.threads = static_cast<int>(state.range(1));
  for (auto _ : state)
    benchmark::DoNotOptimize(similarity::similarity_rows(histograms, layout, index, 0, n, options));
  state.counters["frames"] = static_cast<double>(n);
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(n * n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak_rss_mb"] = core::peak_rss_mb();  // of the whole run so far: run one size alone to read it
}
BENCHMARK(BM_SimilarityMatrix)
    ->Args({200, 2})->Args({500, 2})->Args({1500, 2})->Args({500, 1})->Args({2000, 2})->Args({4000, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_HistogramMatch(benchmark::State& state) {
  const similarity::ShapeHistogramOptions layout;
  const RowMatrix histograms = random_histograms(2, layout);
  const auto search = state.range(0) == 0 ? similarity::RotationSearch::fft : similarity::RotationSearch::exhaustive;
  for (auto _ : state)
    benchmark::DoNotOptimize(similarity::match_histograms(histograms.row(0).data(), histograms.row(1).data(), layout, search));
  state.SetLabel(state.range(0) == 0 ? "fft" : "exhaustive");
}
BENCHMARK(BM_HistogramMatch)->Arg(0)->Arg(1);

/// The tree of N frames from their N×N costs (the tree stage's work after reading the matrix).
void BM_SpanningTree(benchmark::State& state) {
  const long n = state.range(0);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(0, 1);
  // Frames on a smooth 3-D curve plus noise: banded similarity like a real capture.
  Eigen::MatrixXd points(n, 3);
  for (long i = 0; i < n; ++i)
    points.row(i) << std::sin(0.05 * i) + 0.1 * uniform(random), std::cos(0.031 * i), 0.1 * uniform(random);
  Eigen::MatrixXd costs(n, n);
  for (long i = 0; i < n; ++i)
    for (long j = 0; j < n; ++j) costs(i, j) = (points.row(i) - points.row(j)).norm();
  for (auto _ : state) benchmark::DoNotOptimize(similarity::similarity_tree(costs));
  state.counters["frames"] = static_cast<double>(n);
  state.counters["peak_rss_mb"] = core::peak_rss_mb();
}
BENCHMARK(BM_SpanningTree)->Arg(1500)->Arg(2000)->Arg(4000)->Unit(benchmark::kMillisecond);

}  // namespace
