// Blend benchmarks at the paper's 5,580 vertices (casas2011 Table 1): a connected 5,580-vertex
// patch of the dance template (breadth-first growth over faces from vertex 0), frames 0 and 150.
// Skipped when /work/shared/data/dance is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <queue>

#include "surfcap/blend/hybrid_blend.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"

namespace {

using namespace surfcap;

constexpr long kVertices = 5580;
const std::filesystem::path kDance = "/work/shared/data/dance";

struct DanceFixture {
  core::Mesh patch;
  Eigen::MatrixXd a, b;
  std::unique_ptr<blend::NonlinearBlender> blender;
  std::unique_ptr<blend::SourceSet> sources;
  std::unique_ptr<blend::HybridBlend> one, three;
};

/// The first kVertices vertices reached breadth-first through shared faces, and the faces among them.
std::vector<long> grow_patch(const core::Mesh& mesh) {
  std::vector<std::vector<int>> faces_of(static_cast<std::size_t>(mesh.V.rows()));
  for (long k = 0; k < mesh.F.rows(); ++k)
    for (int c = 0; c < 3; ++c) faces_of[mesh.F(k, c)].push_back(static_cast<int>(k));
  std::vector<long> order, index(static_cast<std::size_t>(mesh.V.rows()), -1);
  std::queue<int> queue;
  for (long seed = 0; seed < mesh.V.rows() && static_cast<long>(order.size()) < kVertices; ++seed) {
    if (index[seed] >= 0) continue;
    queue.push(static_cast<int>(seed));
    index[seed] = static_cast<long>(order.size());
    order.push_back(seed);
    while (!queue.empty() && static_cast<long>(order.size()) < kVertices) {
      const int v = queue.front();
      queue.pop();
      for (int f : faces_of[v])
        for (int c = 0; c < 3; ++c) {
          const int w = mesh.F(f, c);
          if (index[w] < 0 && static_cast<long>(order.size()) < kVertices) {
            index[w] = static_cast<long>(order.size());
            order.push_back(w);
            queue.push(w);
          }
        }
    }
  }
  return order;
}

DanceFixture* fixture() {
  static std::unique_ptr<DanceFixture> instance;
  static bool tried = false;
  if (tried) return instance.get();
  tried = true;
  if (!std::filesystem::exists(kDance / "positions.npy")) return nullptr;
  core::MeshRequirements requirements;
  requirements.allow_non_manifold = true;
  requirements.allow_zero_area_faces = true;
  const core::Mesh dance = core::read_mesh(kDance / "template.obj", requirements);
  const std::vector<double> positions = core::read_npy_as_double(kDance / "positions.npy", {-1, dance.V.rows(), 3});
  const std::vector<long> order = grow_patch(dance);
  std::vector<long> index(static_cast<std::size_t>(dance.V.rows()), -1);
  for (std::size_t i = 0; i < order.size(); ++i) index[order[i]] = static_cast<long>(i);
  auto instance_ptr = std::make_unique<DanceFixture>();
  DanceFixture& f = *instance_ptr;
  std::vector<Eigen::RowVector3i> faces;
  for (long k = 0; k < dance.F.rows(); ++k)
    if (index[dance.F(k, 0)] >= 0 && index[dance.F(k, 1)] >= 0 && index[dance.F(k, 2)] >= 0)
      faces.emplace_back(index[dance.F(k, 0)], index[dance.F(k, 1)], index[dance.F(k, 2)]);
  f.patch.F.resize(static_cast<long>(faces.size()), 3);
  for (std::size_t k = 0; k < faces.size(); ++k) f.patch.F.row(static_cast<long>(k)) = faces[k];
  auto frame = [&](long t) {
    Eigen::MatrixXd V(kVertices, 3);
    for (long i = 0; i < kVertices; ++i)
      for (int c = 0; c < 3; ++c) V(i, c) = positions[static_cast<std::size_t>((t * dance.V.rows() + order[i]) * 3 + c)];
    return V;
  };
  f.patch.V = frame(0);
  f.a = frame(0);
  f.b = frame(150);
  f.blender = std::make_unique<blend::NonlinearBlender>(f.patch);
  f.sources = std::make_unique<blend::SourceSet>(*f.blender, std::vector<std::vector<Eigen::MatrixXd>>{{f.a}, {f.b}});
  blend::HybridOptions options;
  options.threads = 1;
  f.one = std::make_unique<blend::HybridBlend>(blend::HybridBlend::with_breakpoints(*f.sources, {{0.5}}, options));
  f.three = std::make_unique<blend::HybridBlend>(
      blend::HybridBlend::with_breakpoints(*f.sources, {{0.25, 0.5, 0.75}}, options));
  instance = std::move(instance_ptr);
  return instance.get();
}

void BM_BlendLinear5580(benchmark::State& state) {
  DanceFixture* f = fixture();
  if (!f) return state.SkipWithError("no /work/shared/data/dance");
  Eigen::MatrixXd mesh;
  for (auto _ : state) {
    f->sources->linear_into(0, {0.37}, mesh);
    benchmark::DoNotOptimize(mesh.data());
  }
  state.counters["vertices"] = static_cast<double>(f->patch.V.rows());
}
BENCHMARK(BM_BlendLinear5580)->Unit(benchmark::kMicrosecond);

void BM_BlendHybrid5580(benchmark::State& state) {
  DanceFixture* f = fixture();
  if (!f) return state.SkipWithError("no /work/shared/data/dance");
  const blend::HybridBlend& hybrid = state.range(0) == 1 ? *f->one : *f->three;
  Eigen::MatrixXd mesh;
  for (auto _ : state) {
    hybrid.evaluate_into(*f->sources, 0, {0.37}, mesh);
    benchmark::DoNotOptimize(mesh.data());
  }
  state.counters["stored_vertices"] = static_cast<double>(hybrid.stored_vertices());
}
BENCHMARK(BM_BlendHybrid5580)->Arg(1)->Arg(3)->Unit(benchmark::kMicrosecond);

/// Exact blend of prepared (decomposed) sources: slerp/lerp per triangle + prefactored Poisson solve.
void BM_BlendExact5580(benchmark::State& state) {
  DanceFixture* f = fixture();
  if (!f) return state.SkipWithError("no /work/shared/data/dance");
  for (auto _ : state) benchmark::DoNotOptimize(f->sources->exact(0, {0.37}, 1).data());
  state.counters["faces"] = static_cast<double>(f->patch.F.rows());
}
BENCHMARK(BM_BlendExact5580)->Unit(benchmark::kMillisecond);

/// Exact blend from raw meshes, including both polar decompositions per triangle.
void BM_BlendExactFromMeshes5580(benchmark::State& state) {
  DanceFixture* f = fixture();
  if (!f) return state.SkipWithError("no /work/shared/data/dance");
  for (auto _ : state) benchmark::DoNotOptimize(f->blender->blend_meshes({&f->a, &f->b}, {0.63, 0.37}, 1).data());
}
BENCHMARK(BM_BlendExactFromMeshes5580)->Unit(benchmark::kMillisecond);

}  // namespace
