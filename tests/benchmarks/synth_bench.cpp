// surfcap-synth's costs: meshing the actor, one frame's pieces (plain and studio reconstructions),
// and the whole tiny preset.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <unistd.h>

#include "surfcap/synth/capture.hpp"
#include "surfcap/synth/studio.hpp"

namespace {

using namespace surfcap;

const synth::Scene& scene() {
  static const synth::Scene s = synth::preset_scene("demo");
  return s;
}
const synth::Actor& actor() {
  static const synth::Actor a(scene());
  return a;
}

void BM_MeshActor(benchmark::State& state) {
  const auto skeleton = synth::make_skeleton();
  const synth::BodyField field(skeleton, {});
  for (auto _ : state) benchmark::DoNotOptimize(synth::mesh_implicit_surface(field, static_cast<int>(state.range(0)), 1));
}
BENCHMARK(BM_MeshActor)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_PerformFrame(benchmark::State& state) {
  const auto& motion = scene().sequences[1];
  actor();  // mesh the actor outside the timed loop
  int frame = 0;
  for (auto _ : state) benchmark::DoNotOptimize(actor().perform(scene(), motion, frame++ % motion.frames));
}
BENCHMARK(BM_PerformFrame)->Unit(benchmark::kMillisecond);

void BM_Reconstruct(benchmark::State& state) {
  core::Mesh truth;
  truth.V = actor().perform(scene(), scene().sequences[0], 3).V;
  truth.F = actor().body.rest.F;
  const double edge = synth::mean_edge_length(actor().body.rest);
  std::uint64_t seed = 1;
  for (auto _ : state) benchmark::DoNotOptimize(synth::reconstruct(truth, edge, seed++));
}
BENCHMARK(BM_Reconstruct)->Unit(benchmark::kMillisecond);

/// One frame of the studio models (visual hull from 8 cameras, floor cut, unseen faces removed,
/// outliers, blobs) at `range(0)` target vertices with a voxel of `range(1)` mm.
void BM_ReconstructStudio(benchmark::State& state) {
  core::Mesh truth;
  truth.V = actor().perform(scene(), scene().sequences[0], 3).V;
  truth.F = actor().body.rest.F;
  const auto cameras = render::ring_cameras(8, 5.0, 1.8, Eigen::Vector3d(0, 0.9, 0), 34, 640, 480);
  synth::ReconstructionOptions options;
  options.visual_hull = true;
  options.vertices = static_cast<int>(state.range(0));
  options.voxel = options.surface_tolerance = static_cast<double>(state.range(1)) / 1000;
  options.floor_cut = true;
  options.unseen = synth::UnseenMode::remove;
  options.outlier_fraction = 0.002;
  options.blobs = 1;
  const double edge = synth::mean_edge_length(actor().body.rest);
  std::uint64_t seed = 1;
  for (auto _ : state) benchmark::DoNotOptimize(synth::reconstruct_studio(truth, cameras, {}, edge, seed++, options));
}
BENCHMARK(BM_ReconstructStudio)->Args({3000, 20})->Args({37000, 6})->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_RenderCamera(benchmark::State& state) {
  core::Mesh truth;
  truth.V = actor().perform(scene(), scene().sequences[0], 3).V;
  truth.F = actor().body.rest.F;
  const auto cameras = render::ring_cameras(8, 5.0, 1.8, Eigen::Vector3d(0, 0.9, 0), 34, 640, 480);
  const auto options = actor().render_options();
  for (auto _ : state) benchmark::DoNotOptimize(render::render_mesh(truth, cameras[1], options));
}
BENCHMARK(BM_RenderCamera)->Unit(benchmark::kMillisecond);

void BM_TinyPreset(benchmark::State& state) {
  const auto directory = std::filesystem::temp_directory_path() / ("synth-bench-" + std::to_string(::getpid()));
  const synth::Scene tiny = synth::preset_scene("tiny");
  for (auto _ : state) {
    core::StageReport report("synth");
    synth::generate_capture(tiny, directory, 2, report);
  }
  std::filesystem::remove_all(directory);
}
BENCHMARK(BM_TinyPreset)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
