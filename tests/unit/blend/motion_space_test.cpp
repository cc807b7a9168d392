#include "surfcap/blend/motion_space.hpp"

#include <gtest/gtest.h>

#include "procedural_limb.hpp"
#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/npy.hpp"
#include "test_support.hpp"

namespace surfcap::blend {
namespace {

/// A database of two "gaits": the limb swinging ±`swing` rad per cycle while the root advances
/// at `speed` m/s; different frame counts so that the time warp matters.
core::AlignedDatabase limb_database() {
  core::AlignedDatabase database;
  database.template_mesh = testing::make_tube(12, 8);
  database.fps = 25;
  auto gait = [&](const std::string& name, int frames, double swing, double speed) {
    core::AlignedSequence sequence;
    sequence.name = name;
    for (int k = 0; k < frames; ++k) {
      const double phase = 2 * M_PI * k / (frames - 1);
      Eigen::MatrixXd V = testing::pose_tube(database.template_mesh, swing * std::sin(phase), 0.0);
      sequence.frames.push_back(V.rowwise() - V.colwise().mean());
      sequence.root_motion.push_back({speed * k / database.fps, 0.5 + 0.02 * std::sin(2 * phase), 0.0, 0.0});
    }
    database.sequences.push_back(sequence);
  };
  gait("walk", 17, 0.5, 1.2);
  gait("run", 11, 1.2, 3.0);
  database.root_sequence = "walk";
  return database;
}

TEST(MotionSpace, BuildsWritesAndMapsSpeedToWeights) {
  const core::AlignedDatabase database = limb_database();
  surfcap::testing::TemporaryDirectory directory("blend_motion_space");
  const SpaceConfig config = parse_space_config(core::Json::parse(R"(
    {"name": "gait", "sequences": ["walk", "run"], "cyclic": true, "frames": 9, "tolerance_mm": 5,
     "parameters": [{"name": "speed", "measure": "root_speed"}]})"), directory / "graph.json");
  const NonlinearBlender blender(database.template_mesh);
  MotionSpaceOptions options;
  options.sweep_tolerances_mm = {5, 20};
  options.validation_samples = 4;
  const MotionSpace space = build_motion_space(database, blender, config, options);

  // Warps: start and end of each cycle aligned, monotone.
  ASSERT_EQ(space.warps.size(), 2u);
  EXPECT_DOUBLE_EQ(space.warps[1].front(), 0.0);
  EXPECT_DOUBLE_EQ(space.warps[1].back(), 10.0);
  for (std::size_t k = 1; k < space.warps[1].size(); ++k) EXPECT_GE(space.warps[1][k], space.warps[1][k - 1]);

  // Speed is measured from the blended root motion: 1.2 m/s at u = 0, 3 m/s at u = 1.
  EXPECT_NEAR(measure_parameters(space, {0.0})[0], 1.2, 1e-6);
  EXPECT_NEAR(measure_parameters(space, {1.0})[0], 3.0, 1e-6);
  ASSERT_TRUE(space.parameter_map.has_value());
  EXPECT_LT(space.parameter_map->residual_max, 0.05);
  const double u = space.parameter_map->weights_for({measure_parameters(space, {0.3})[0]})[0];
  EXPECT_NEAR(u, 0.3, 0.05);
  EXPECT_LE(space.figures["validation"]["hybrid_max_error_mm"].get<double>(), 5.0);

  write_motion_space(directory.path(), space);
  const core::Json entry = core::read_json_document(directory / "spaces" / "gait" / "space.json", "space", 1)["space"];
  EXPECT_EQ(entry["name"], "gait");
  EXPECT_EQ(entry["weights"].size(), static_cast<std::size_t>(space.hybrid->node_count()));
  EXPECT_EQ(entry["parameters"][0]["measure"], "root_speed");
  const core::NpyArray references = core::read_npy(directory.path() / entry["references"].get<std::string>());
  EXPECT_EQ(references.shape, (std::vector<std::size_t>{2, 9, 96, 3}));
  const core::NpyArray offsets = core::read_npy(directory.path() / entry["displacements"]["offsets"].get<std::string>());
  EXPECT_EQ(offsets.shape[0], static_cast<std::size_t>(space.hybrid->node_count() * 9 + 1));
  const core::NpyArray values = core::read_npy(directory.path() / entry["displacements"]["values"].get<std::string>());
  EXPECT_EQ(values.dtype, core::DType::float16);
  EXPECT_EQ(static_cast<long>(values.shape[0]), space.hybrid->stored_vertices());
  const std::string png = core::read_file(directory.path() / entry["time_warp_plot"].get<std::string>());
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(surfcap::testing::count_hidden_files(directory.path() / "spaces" / "gait"), 0);
}

TEST(SpaceConfig, ReadsRangesParametersAndDefaults) {
  const SpaceConfig config = parse_space_config(core::Json::parse(R"(
    {"name": "reach", "sequences": [{"name": "low", "first": 2, "last": 9}, "high"],
     "parameters": [{"name": "height", "measure": "hand_height", "vertices": [4, 7]}]})"), "reach.json");
  EXPECT_EQ(config.source, "reach.json");
  ASSERT_EQ(config.sequences.size(), 2u);
  EXPECT_EQ(config.sequences[0].first, 2);
  EXPECT_EQ(config.sequences[0].last, 9);
  EXPECT_EQ(config.sequences[1].name, "high");
  EXPECT_EQ(config.sequences[1].last, -1);
  ASSERT_EQ(config.parameters.size(), 1u);
  EXPECT_EQ(config.parameters[0].measure, Measure::hand_height);
  EXPECT_EQ(config.parameters[0].vertices, (std::vector<int>{4, 7}));
  EXPECT_FALSE(config.cyclic);
  EXPECT_EQ(config.frames, 0);
  EXPECT_DOUBLE_EQ(config.tolerance_mm, 5.0);
  EXPECT_EQ(config.degree, 2);
}

TEST(SpaceConfig, RejectsUnknownMeasuresAndMismatchedParameters) {
  EXPECT_THROW(parse_space_config(core::Json::parse(R"({"name": "s", "sequences": ["a", "b"],
    "parameters": [{"name": "p", "measure": "wobble"}]})"), "bad.json"), core::Error);
  EXPECT_THROW(parse_space_config(core::Json::parse(R"({"name": "s", "sequences": ["a", "b", "c"],
    "parameters": [{"name": "p", "measure": "root_speed"}]})"), "three.json"), core::Error);
  EXPECT_THROW(parse_space_config(core::Json::parse(R"({"name": "s", "sequences": ["a", "b"],
    "parameters": [{"name": "p", "measure": "hand_height"}]})"), "hand.json"), core::Error);
}

}  // namespace
}  // namespace surfcap::blend
