// Learning, storage and example selection of part models, and automatic decomposition.
#include <gtest/gtest.h>

#include <filesystem>

#include "articulated_figure.hpp"
#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/geometry/cotangent_laplacian.hpp"
#include "surfcap/geometry/mesh_topology.hpp"
#include "surfcap/learn/automatic_parts.hpp"
#include "surfcap/learn/edit_file.hpp"
#include "surfcap/learn/part_model.hpp"
#include "surfcap/learn/parts_preview.hpp"
#include "test_support.hpp"

namespace surfcap::learn {
namespace {

const core::AlignedDatabase& small_figure() {
  static const core::AlignedDatabase db = testing::figure_database(0.045, 24, 3);
  return db;
}
const std::filesystem::path human6 = std::filesystem::path(SURFCAP_SOURCE_DIR) / "configs/parts/human6.json";

TEST(PartModel, BasisSpansTheExamplesAndRoundTripsThroughFiles) {
  const auto& db = small_figure();
  const PartSet parts = read_part_config(human6, db.template_mesh);
  const auto examples = strided_frames(db, 3);
  LearnOptions options;
  options.energy = 1.0;  // keep everything: every example lies in its part's space
  const LearntModel model = learn_part_models(db, parts, examples, options);
  for (const PartModel& p : model.parts) {
    const auto sub = geometry::extract_submesh(db.template_mesh.F, db.template_mesh.vertex_count(), p.part.vertices);
    Eigen::MatrixXd rest(static_cast<Eigen::Index>(sub.vertices.size()), 3);
    for (std::size_t i = 0; i < sub.vertices.size(); ++i) rest.row(static_cast<Eigen::Index>(i)) = db.template_mesh.V.row(sub.vertices[i]);
    const auto L = geometry::cotangent_laplacian(rest, sub.F);
    EXPECT_LT((p.basis.transpose() * p.basis - Eigen::MatrixXd::Identity(p.basis.cols(), p.basis.cols())).norm(), 1e-8);
    EXPECT_LT(p.basis.cols(), static_cast<long>(examples.size()));  // mean-centred: at most F − 1 vectors
    const Eigen::VectorXd delta = part_differential_coordinates(L, p.part.vertices, db.sequences[0].frames[3]);
    const Eigen::VectorXd centred = delta - p.mean;
    EXPECT_LT((centred - p.basis * (p.basis.transpose() * centred)).norm(), 1e-6 * (1 + centred.norm())) << p.part.name;
  }
  // 95% energy keeps fewer vectors and reports the share.
  const LearntModel truncated = learn_part_models(db, parts, examples, {});
  EXPECT_GE(truncated.parts[0].energy, 0.95);
  EXPECT_LE(truncated.parts[0].basis.cols(), model.parts[0].basis.cols());

  testing::TemporaryDirectory dir("learn_model");
  write_learnt_model(dir.path(), truncated);
  EXPECT_EQ(testing::count_hidden_files(dir.path() / "parts"), 0);
  const LearntModel read = read_learnt_model(dir / "parts.json");
  ASSERT_EQ(read.parts.size(), truncated.parts.size());
  for (std::size_t j = 0; j < read.parts.size(); ++j) {
    EXPECT_EQ(read.parts[j].part.name, truncated.parts[j].part.name);
    EXPECT_EQ(read.parts[j].part.parent, truncated.parts[j].part.parent);
    EXPECT_EQ(read.parts[j].part.vertices, truncated.parts[j].part.vertices);
    EXPECT_LT((read.parts[j].basis - truncated.parts[j].basis).cwiseAbs().maxCoeff(), 1e-6);  // float32 storage
  }
  EXPECT_EQ(read.regions, truncated.regions);
  EXPECT_EQ(read.examples.size(), examples.size());
  const auto doc = core::read_json_document(dir / "parts.json", "parts", 1);
  EXPECT_EQ(doc["parts"][1]["parent"], "torso");
}

TEST(ExampleSelection, FarthestPoseSamplingKeepsTheExtremePose) {
  core::AlignedDatabase db = small_figure();
  // Make one frame an outlier: it must be among the first picks.
  db.sequences[0].frames[17].col(1) *= 1.5;
  const auto picked = farthest_pose_frames(db, 3);
  ASSERT_EQ(picked.size(), 3u);
  EXPECT_NE(std::find(picked.begin(), picked.end(), ExampleFrame{0, 17}), picked.end());
  EXPECT_EQ(farthest_pose_frames(db, 3), picked);  // deterministic
  EXPECT_EQ(parse_frame_list(db, "motion:2,motion:5").size(), 2u);
  EXPECT_THROW(parse_frame_list(db, "motion:99"), core::Error);
  EXPECT_THROW(parse_frame_list(db, "walk:1"), core::Error);
}

TEST(AutomaticParts, NearRigidClustersSeparateTheLimbs) {
  const auto& db = small_figure();
  AutomaticPartsOptions options;
  options.parts = 6;
  const PartSet parts = automatic_parts(db, all_frames(db), options);
  ASSERT_EQ(parts.parts.size(), 6u);
  // The two hands move independently: they must not fall in the same part's own (non-overlap) region.
  const Extremities e = find_extremities(db.template_mesh);
  auto owner = [&](int v) {
    int best = -1;
    for (std::size_t j = 0; j < parts.parts.size(); ++j)
      if (std::binary_search(parts.parts[j].vertices.begin(), parts.parts[j].vertices.end(), v)) best = static_cast<int>(j);
    return best;
  };
  EXPECT_NE(owner(e.vertices.at("hand_l")), owner(e.vertices.at("hand_r")));
  EXPECT_NE(owner(e.vertices.at("foot_l")), owner(e.vertices.at("foot_r")));
  // The config it writes evaluates back to the same parts.
  const PartSet again = evaluate_part_config(part_config_with_vertex_lists(parts), db.template_mesh, "auto");
  ASSERT_EQ(again.parts.size(), parts.parts.size());
  for (std::size_t j = 0; j < parts.parts.size(); ++j) EXPECT_EQ(again.parts[j].vertices, parts.parts[j].vertices);
}

TEST(EditFile, SelectorsAndTargets) {
  const auto& db = small_figure();
  const PartSet parts = read_part_config(human6, db.template_mesh);
  const core::Json edit = core::Json::parse(R"({"format": "surfcap.edit/1",
      "anchors": [{"part_core": "torso"}],
      "handles": [{"region": "hand_l", "translate": [0, 0.1, 0], "weight": 2}, {"vertices": [0], "positions": [[1, 2, 3]]}]})");
  const auto constraints = edit_constraints(edit, parts, db.template_mesh.V, "edit.json");
  const auto& hand = parts.regions.at("hand_l");
  EXPECT_EQ(constraints.back().vertex, 0);
  EXPECT_EQ(constraints.back().target, Eigen::Vector3d(1, 2, 3));
  const auto& first_hand = constraints[constraints.size() - 1 - hand.size()];
  EXPECT_DOUBLE_EQ(first_hand.weight, 2);
  EXPECT_NEAR(first_hand.target.y() - db.template_mesh.V(first_hand.vertex, 1), 0.1, 1e-12);
  EXPECT_THROW(edit_constraints(core::Json::parse(R"({"handles": [{"region": "tail"}]})"), parts, db.template_mesh.V, "e"),
               core::Error);
}

TEST(PartsPreview, WritesAPng) {
  const auto& db = small_figure();
  testing::TemporaryDirectory dir("learn_preview");
  write_parts_preview(dir / "parts.png", db.template_mesh, read_part_config(human6, db.template_mesh), 256);
  const std::string bytes = core::read_file(dir / "parts.png");
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
}

}  // namespace
}  // namespace surfcap::learn
