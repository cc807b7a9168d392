// Learnt part-based editing on an in-test articulated figure (tests/unit/learn/articulated_figure.hpp).
#include <gtest/gtest.h>

#include <filesystem>

#include "articulated_figure.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/learn/leave_out.hpp"
#include "surfcap/learn/part_editor.hpp"
#include "surfcap/learn/part_set.hpp"
#include "test_support.hpp"

namespace surfcap::learn {
namespace {

const std::filesystem::path human6 = std::filesystem::path(SURFCAP_SOURCE_DIR) / "configs/parts/human6.json";

struct Figure {
  core::AlignedDatabase database = testing::figure_database(0.03, 64, 7);
  PartSet parts = read_part_config(human6, database.template_mesh);
};
const Figure& figure() {
  static const Figure instance;
  return instance;
}

TEST(PartConfig, Human6FindsSixOverlappingPartsWithTorsoRoot) {
  const PartSet& parts = figure().parts;
  ASSERT_EQ(parts.parts.size(), 6u);
  EXPECT_EQ(parts.parts[0].name, "torso");
  const core::Mesh& mesh = figure().database.template_mesh;
  for (std::size_t j = 1; j < parts.parts.size(); ++j) {
    const Part& p = parts.parts[j];
    EXPECT_EQ(p.parent, 0) << p.name;
    EXPECT_FALSE(p.frontier.empty()) << p.name;
    // Every limb sits on its side of the body: arms/legs left at +x, right at −x, head above the shoulders.
    double mean_x = 0, min_y = 1e9;
    for (int v : p.vertices) mean_x += mesh.V(v, 0), min_y = std::min(min_y, mesh.V(v, 1));
    mean_x /= p.vertices.size();
    if (p.name.ends_with("_l")) EXPECT_GT(mean_x, 0.08) << p.name;
    if (p.name.ends_with("_r")) EXPECT_LT(mean_x, -0.08) << p.name;
    if (p.name == "head") EXPECT_GT(min_y, 1.3);
    if (p.name.starts_with("arm")) EXPECT_GT(min_y, 1.2) << p.name;  // arms stay off the hips
  }
  // Hands are the far tips of the arms.
  for (int v : parts.regions.at("hand_l")) EXPECT_GT(mesh.V(v, 0), 0.6);
  for (int v : parts.regions.at("foot_r")) EXPECT_LT(mesh.V(v, 1), 0.25);
}

TEST(PartEditor, ReproducesTheReferencePoseWhenConstraintsAreMet) {
  const auto& db = figure().database;
  const LearntModel model = learn_part_models(db, figure().parts, strided_frames(db, 4), {});
  const Eigen::MatrixXd pose = db.sequences[0].frames[5];
  const PartEditor editor(model, {}, pose);
  std::vector<Constraint> constraints;
  for (int v : figure().parts.regions.at("hand_l")) constraints.push_back({v, pose.row(v).transpose(), 1});
  const Eigen::MatrixXd edited = editor.edit(constraints);
  EXPECT_LT((edited - pose).rowwise().norm().maxCoeff(), 1e-7);
}

TEST(PartEditor, EditingOneLimbLeavesTheOtherLimbsStill) {
  // tejera2013 Fig. 2: drag the left foot backwards with the torso anchored. The part-based
  // editor must not move an unconstrained limb by more than 1 mm; the global basis does.
  const auto& db = figure().database;
  const auto examples = strided_frames(db, 2);
  const LearntModel parts_model = learn_part_models(db, figure().parts, examples, {});
  const LearntModel global_model = learn_part_models(db, whole_mesh_part(db.template_mesh.vertex_count()), examples, {});
  const Eigen::MatrixXd start = db.sequences[0].frames[10];
  const PartSet& parts = figure().parts;
  std::vector<Constraint> constraints;
  const Part& torso = parts.parts[0];
  std::set<int> limb_vertices;
  for (std::size_t j = 1; j < parts.parts.size(); ++j) limb_vertices.insert(parts.parts[j].vertices.begin(), parts.parts[j].vertices.end());
  for (int v : torso.vertices)
    if (!limb_vertices.count(v)) constraints.push_back({v, start.row(v).transpose(), 1});
  const Eigen::Vector3d drag(0, 0.05, -0.12);
  for (int v : parts.regions.at("foot_l")) constraints.push_back({v, start.row(v).transpose() + drag, 1});

  const Eigen::MatrixXd part_edit = PartEditor(parts_model, {}, start).edit(constraints);
  const Eigen::MatrixXd global_edit = PartEditor(global_model, {}, start).edit(constraints);
  // The handle moved.
  double handle_motion = 0;
  for (int v : parts.regions.at("foot_l")) handle_motion += (part_edit.row(v) - start.row(v)).norm();
  EXPECT_GT(handle_motion / parts.regions.at("foot_l").size(), 0.08);
  for (const char* name : {"leg_r", "arm_l", "arm_r", "head"}) {
    const Part& limb = parts.parts[parts.find(name)];
    double part_moved = 0, global_moved = 0;
    for (int v : limb.vertices) {
      if (std::binary_search(parts.parts[parts.find("leg_l")].vertices.begin(),
                             parts.parts[parts.find("leg_l")].vertices.end(), v))
        continue;
      part_moved = std::max(part_moved, (part_edit.row(v) - start.row(v)).norm());
      global_moved = std::max(global_moved, (global_edit.row(v) - start.row(v)).norm());
    }
    EXPECT_LT(part_moved, 1e-3) << name;
    RecordProperty(std::string("global_moved_mm_") + name, std::to_string(1e3 * global_moved));
    if (std::string(name) == "leg_r") EXPECT_GT(global_moved, 1e-3) << "the global basis should drag the other leg";
  }
}

TEST(PartEditor, LeaveOutPartBasedBeatsLaplacianAndGlobalBasis) {
  LeaveOutOptions options;
  options.stride = 4;
  options.max_evaluated = 12;
  const LeaveOutResult result = leave_out_evaluation(figure().database, figure().parts, options);
  const auto& parts = result.method("parts");
  const auto& global = result.method("global");
  const auto& laplacian = result.method("laplacian");
  for (const auto& m : result.methods)
    std::printf("leave-out %-9s mean %.2f mm max %.2f mm\n", m.method.c_str(), 1e3 * m.mean_error, 1e3 * m.max_error);
  EXPECT_EQ(result.training_frames, 16);
  EXPECT_LT(parts.mean_error, global.mean_error);
  EXPECT_LT(parts.mean_error, laplacian.mean_error);
  EXPECT_LT(parts.mean_error, 0.02);  // sanity: a reconstruction, not noise (figure is 1.8 m tall)
}

TEST(PartEditor, RejectsOutOfRangeConstraint) {
  const auto& db = figure().database;
  const LearntModel model = learn_part_models(db, figure().parts, strided_frames(db, 8), {});
  const PartEditor editor(model, {});
  EXPECT_THROW(editor.edit({{static_cast<int>(db.template_mesh.vertex_count()), Eigen::Vector3d::Zero(), 1}}),
               core::Error);
}

}  // namespace
}  // namespace surfcap::learn
