// character.glb export and load times for a 3k-vertex character: the synth demo actor (3,000-
// vertex template with its colours) performing the demo's four sequences (144 frames), plus a
// 1-D and a 2-D space of 40 frames with 5 bisection nodes and 30 % stored displacements, a
// transition between them and two parts (sizes like surfcap-precompute's output on demo; the
// space arrays hold random values: the file stores them raw, so only their sizes matter).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <unistd.h>

#include "../unit/asset/synthetic_character.hpp"
#include "surfcap/asset/glb_character.hpp"
#include "surfcap/synth/capture.hpp"

namespace {

using namespace surfcap;

core::Mesh demo_template(const synth::Actor& actor) {
  core::Mesh mesh = actor.body.rest;
  mesh.colors = synth::vertex_albedo(actor.body, actor.texture);
  mesh.colors = (mesh.colors.array().max(0.0).min(1.0) * 255).round() / 255;  // as template.ply stores them
  return mesh;
}

const asset::Character& demo_character() {
  static const asset::Character character = [] {
    const synth::Scene scene = synth::preset_scene("demo");
    const synth::Actor actor(scene);
    testing::SyntheticCharacterShape shape;
    shape.frames = 40;
    shape.extra_nodes = 5;
    shape.stored_share = 0.3;
    asset::Character c = testing::synthetic_character(demo_template(actor), shape);
    c.template_mesh.uvs.resize(0, 2);
    c.sequences.clear();
    for (const synth::MotionSpec& motion : scene.sequences) {
      core::AlignedSequence sequence;
      sequence.name = motion.name;
      for (int t = 0; t < motion.frames; ++t) {
        const Eigen::MatrixXd world = actor.perform(scene, motion, t).V;
        const Eigen::RowVector3d centre = world.colwise().mean();
        const core::RootMotion root{static_cast<float>(centre.x()), 0.0, static_cast<float>(centre.z()), 0.0};
        sequence.frames.push_back(core::to_centred(world, root).cast<float>().cast<double>());
        sequence.root_motion.push_back(root);
      }
      c.sequences.push_back(std::move(sequence));
    }
    for (auto& space : c.spaces)
      for (int i = 0; i < space.source_count(); ++i) space.sources[i].sequence = c.sequences[i % 2].name;
    return c;
  }();
  return character;
}

std::filesystem::path scratch(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("asset-bench-" + std::to_string(::getpid()) + "-" + name);
}

void BM_CharacterGlbEncode3k(benchmark::State& state) {
  const asset::Character& c = demo_character();
  asset::GlbSummary summary;
  for (auto _ : state) benchmark::DoNotOptimize(asset::character_glb_bytes(c, {}, &summary));
  state.counters["MB"] = summary.file_bytes / 1e6;
  state.counters["vertices"] = static_cast<double>(c.vertex_count());
  for (const auto& [kind, bytes] : summary.buffer_bytes) state.counters[kind + "_MB"] = bytes / 1e6;
}
BENCHMARK(BM_CharacterGlbEncode3k)->Unit(benchmark::kMillisecond);

void BM_CharacterGlbExport3k(benchmark::State& state) {  // encode + atomic write (fsync, rename)
  const asset::Character& c = demo_character();
  const auto path = scratch("character.glb");
  for (auto _ : state) asset::write_character_glb(path, c);
  state.counters["MB"] = std::filesystem::file_size(path) / 1e6;
  std::filesystem::remove(path);
}
BENCHMARK(BM_CharacterGlbExport3k)->Unit(benchmark::kMillisecond);

void BM_CharacterGlbLoad3k(benchmark::State& state) {  // read the file + parse + check
  const auto path = scratch("load.glb");
  asset::write_character_glb(path, demo_character());
  for (auto _ : state) benchmark::DoNotOptimize(asset::read_character_glb(path));
  state.counters["MB"] = std::filesystem::file_size(path) / 1e6;
  std::filesystem::remove(path);
}
BENCHMARK(BM_CharacterGlbLoad3k)->Unit(benchmark::kMillisecond);

}  // namespace
