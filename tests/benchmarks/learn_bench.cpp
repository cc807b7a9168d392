// Learnt part-based editing: time of one edit (deformation + recombination) at ~1,600 and ~10k
// vertices on the procedural figure, and the leave-out comparison on ../shared/data/dance.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <set>

#include "../unit/learn/articulated_figure.hpp"
#include "surfcap/learn/array_database.hpp"
#include "surfcap/learn/leave_out.hpp"
#include "surfcap/learn/part_editor.hpp"

namespace {

using namespace surfcap;
const std::filesystem::path human6 = std::filesystem::path(SURFCAP_SOURCE_DIR) / "configs/parts/human6.json";

// tejera2013 Fig. 2 edit: drag the left foot, torso core anchored. Arg: grid spacing in 0.1 mm.
void BM_PartEdit(benchmark::State& state) {
  const core::AlignedDatabase db = testing::figure_database(state.range(0) * 1e-4, 64, 7);
  const learn::PartSet parts = learn::read_part_config(human6, db.template_mesh);
  const learn::LearntModel model = learn::learn_part_models(db, parts, learn::strided_frames(db, 2), {});
  const Eigen::MatrixXd start = db.sequences[0].frames[10];
  const learn::PartEditor editor(model, {}, start);
  std::set<int> limbs;
  for (std::size_t j = 1; j < parts.parts.size(); ++j) limbs.insert(parts.parts[j].vertices.begin(), parts.parts[j].vertices.end());
  std::vector<int> vertices;
  for (int v : parts.parts[0].vertices)
    if (!limbs.count(v)) vertices.push_back(v);
  const std::size_t anchors = vertices.size();
  for (int v : parts.regions.at("foot_l")) vertices.push_back(v);
  const auto handles = editor.prepare(vertices, std::vector<double>(vertices.size(), 1.0));
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i) targets.row(static_cast<Eigen::Index>(i)) = start.row(vertices[i]);
  double step = 0;
  for (auto _ : state) {
    step += 0.01;  // a new drag target every edit: only right-hand sides change
    for (std::size_t i = anchors; i < vertices.size(); ++i)
      targets.row(static_cast<Eigen::Index>(i)) = start.row(vertices[i]) + Eigen::RowVector3d(0, 0.05, -0.1 - 0.05 * std::sin(step));
    benchmark::DoNotOptimize(editor.solve(*handles, targets));
  }
  state.counters["vertices"] = static_cast<double>(db.template_mesh.vertex_count());
  state.SetLabel("part-based, 3 rotation updates");
}
BENCHMARK(BM_PartEdit)->Arg(400)->Arg(160)->Unit(benchmark::kMillisecond);

// Every part moves: head, hands and feet dragged towards another pose, nothing anchored (the
// root is placed by the coupled solve, then all five children are solved and recombined).
void BM_PartEditAllParts(benchmark::State& state) {
  const core::AlignedDatabase db = testing::figure_database(state.range(0) * 1e-4, 64, 7);
  const learn::PartSet parts = learn::read_part_config(human6, db.template_mesh);
  const learn::LearntModel model = learn::learn_part_models(db, parts, learn::strided_frames(db, 2), {});
  const learn::PartEditor editor(model, {}, db.sequences[0].frames[10]);
  std::set<int> chosen;
  for (const char* region : {"head", "hand_l", "hand_r", "foot_l", "foot_r"})
    chosen.insert(parts.regions.at(region).begin(), parts.regions.at(region).end());
  const std::vector<int> vertices(chosen.begin(), chosen.end());
  const auto handles = editor.prepare(vertices, std::vector<double>(vertices.size(), 1.0));
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(vertices.size()), 3);
  int frame = 0;
  for (auto _ : state) {
    frame = (frame + 7) % 64;  // true positions of another frame
    for (std::size_t i = 0; i < vertices.size(); ++i)
      targets.row(static_cast<Eigen::Index>(i)) = db.sequences[0].frames[frame].row(vertices[i]);
    benchmark::DoNotOptimize(editor.solve(*handles, targets));
  }
  state.counters["vertices"] = static_cast<double>(db.template_mesh.vertex_count());
}
BENCHMARK(BM_PartEditAllParts)->Arg(400)->Arg(160)->Unit(benchmark::kMillisecond);

// Leave-out on dance: learn from every 4th frame, reconstruct held-out frames from head, hands, feet.
void BM_DanceLeaveOut(benchmark::State& state) {
  const std::filesystem::path dance = std::filesystem::path(SURFCAP_SOURCE_DIR) / "../shared/data/dance";
  if (!std::filesystem::exists(dance / "positions.npy")) {
    state.SkipWithError("../shared/data/dance absent");
    return;
  }
  const core::AlignedDatabase db = learn::database_from_positions(dance / "template.obj", dance / "positions.npy", "dance");
  const learn::PartSet parts = learn::read_part_config(human6, db.template_mesh);
  learn::LeaveOutOptions options;
  options.stride = 4;
  options.max_evaluated = 24;
  learn::LeaveOutResult result;
  for (auto _ : state) result = learn::leave_out_evaluation(db, parts, options);
  for (const auto& m : result.methods) {
    state.counters[m.method + "_mean_mm"] = 1e3 * m.mean_error;
    state.counters[m.method + "_max_mm"] = 1e3 * m.max_error;
    state.counters[m.method + "_ms_per_edit"] = 1e3 * m.seconds_per_edit;
  }
  state.counters["vertices"] = static_cast<double>(db.template_mesh.vertex_count());
}
BENCHMARK(BM_DanceLeaveOut)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
