// Core I/O throughput: binary PLY read/write of a 10k-vertex coloured mesh, .npy of a sequence.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "surfcap/core/mesh.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"

namespace {

using surfcap::core::Mesh;

/// A UV sphere with (rings-1)·segments + 2 vertices and per-vertex colours.
Mesh sphere(int rings, int segments) {
  Mesh mesh;
  const int n = (rings - 1) * segments + 2;
  mesh.V.resize(n, 3);
  mesh.colors.resize(n, 3);
  mesh.V.row(0) << 0, 1, 0;
  mesh.V.row(n - 1) << 0, -1, 0;
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      mesh.V.row(1 + (r - 1) * segments + s) << std::sin(theta) * std::cos(phi), std::cos(theta),
          std::sin(theta) * std::sin(phi);
    }
  for (int v = 0; v < n; ++v) mesh.colors.row(v) << (v % 7) / 6.0, (v % 5) / 4.0, (v % 3) / 2.0;
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

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("surfcap-bench-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

const Mesh& mesh_10k() {
  static const Mesh mesh = sphere(71, 141);  // 9,872 vertices, 19,740 faces
  return mesh;
}

void BM_WritePlyBinary10k(benchmark::State& state) {
  const auto path = scratch("write.ply");
  for (auto _ : state) surfcap::core::write_mesh(path, mesh_10k());
  state.counters["vertices"] = static_cast<double>(mesh_10k().vertex_count());
  state.counters["vertices_per_s"] =
      benchmark::Counter(static_cast<double>(mesh_10k().vertex_count()), benchmark::Counter::kIsIterationInvariantRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * std::filesystem::file_size(path)));
  std::filesystem::remove(path);
}
BENCHMARK(BM_WritePlyBinary10k)->Unit(benchmark::kMillisecond);

void BM_ReadPlyBinary10k(benchmark::State& state) {
  const auto path = scratch("read.ply");
  surfcap::core::write_mesh(path, mesh_10k());
  for (auto _ : state) benchmark::DoNotOptimize(surfcap::core::read_mesh(path));
  state.counters["vertices_per_s"] =
      benchmark::Counter(static_cast<double>(mesh_10k().vertex_count()), benchmark::Counter::kIsIterationInvariantRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * std::filesystem::file_size(path)));
  std::filesystem::remove(path);
}
BENCHMARK(BM_ReadPlyBinary10k)->Unit(benchmark::kMillisecond);

void BM_ValidateMesh10k(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(surfcap::core::check_mesh(mesh_10k()));
}
BENCHMARK(BM_ValidateMesh10k)->Unit(benchmark::kMillisecond);

void BM_NpySequenceRoundTrip(benchmark::State& state) {
  // One 100-frame sequence of a 10k-vertex character: float32 [100, 10000, 3] = 12 MB.
  std::vector<float> values(100 * 10000 * 3, 0.25f);
  const auto path = scratch("sequence.npy");
  for (auto _ : state) {
    surfcap::core::write_npy(path, values.data(), {100, 10000, 3});
    benchmark::DoNotOptimize(surfcap::core::read_npy(path));
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * values.size() * sizeof(float) * 2));
  std::filesystem::remove(path);
}
BENCHMARK(BM_NpySequenceRoundTrip)->Unit(benchmark::kMillisecond);

}  // namespace
