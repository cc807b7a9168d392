#include "surfcap/graph/graph_config.hpp"

#include <gtest/gtest.h>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/graph/graph_file.hpp"
#include "test_support.hpp"

namespace surfcap::graph {
namespace {

/// Writes a minimal spaces/<name>/space.json whose entry carries `marker`.
void write_space_file(const std::filesystem::path& output, const std::string& name, int marker) {
  core::write_json_file(output / "spaces" / name / "space.json",
                        {{"format", core::format_tag("space", 1)}, {"space", {{"name", name}, {"marker", marker}}}});
}

/// A config of two spaces (only their names set), no transitions.
GraphConfig two_spaces(const std::string& first, const std::string& second) {
  GraphConfig config;
  config.spaces.resize(2);
  config.spaces[0].name = first;
  config.spaces[1].name = second;
  return config;
}

TEST(GraphConfig, ReadsSpacesAndTransitions) {
  surfcap::testing::TemporaryDirectory directory("graph_config_read");
  surfcap::testing::write_text(directory / "graph.json", R"({
    "format": "surfcap.graph_config/1",
    "spaces": [{"name": "gait", "sequences": ["walk", "run"], "cyclic": true, "frames": 9, "tolerance_mm": 5,
                "parameters": [{"name": "speed", "measure": "root_speed"}]},
               {"name": "idle", "sequences": ["stand", "sway"]}],
    "transitions": [{"from": "gait", "to": "idle"}]})");
  const GraphConfig config = read_graph_config(directory / "graph.json");
  ASSERT_EQ(config.spaces.size(), 2u);
  EXPECT_EQ(config.spaces[0].source, directory / "graph.json");
  EXPECT_TRUE(config.spaces[0].cyclic);
  EXPECT_EQ(config.spaces[0].frames, 9);
  EXPECT_EQ(config.spaces[0].parameters[0].measure, blend::Measure::root_speed);
  ASSERT_NE(config.find("idle"), nullptr);
  EXPECT_EQ(config.find("idle")->sequences[0].name, "stand");
  EXPECT_EQ(config.find("jump"), nullptr);
  ASSERT_EQ(config.transitions.size(), 1u);
  EXPECT_EQ(config.transitions[0].from, "gait");
  EXPECT_EQ(config.transitions[0].to, "idle");
}

TEST(GraphConfig, RejectsUnknownMeasuresMismatchedParametersAndUnknownSpaces) {
  surfcap::testing::TemporaryDirectory directory("graph_config_bad");
  const auto expect_bad_input = [&](const std::string& file, const std::string& text, const std::string& wording) {
    surfcap::testing::write_text(directory / file, text);
    try {
      read_graph_config(directory / file);
      ADD_FAILURE() << file << " was accepted";
    } catch (const core::Error& error) {
      EXPECT_EQ(error.code(), core::ExitCode::bad_input) << file;
      EXPECT_NE(std::string(error.what()).find(file), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(wording), std::string::npos) << error.what();
    }
  };
  expect_bad_input("bad.json", R"({"format": "surfcap.graph_config/1",
    "spaces": [{"name": "s", "sequences": ["a", "b"], "parameters": [{"name": "p", "measure": "wobble"}]}]})",
                   "unknown measure 'wobble'");
  expect_bad_input("three.json", R"({"format": "surfcap.graph_config/1",
    "spaces": [{"name": "s", "sequences": ["a", "b", "c"]}]})", "2, 4 or 8 sequences");
  expect_bad_input("twice.json", R"({"format": "surfcap.graph_config/1",
    "spaces": [{"name": "s", "sequences": ["a", "b"]}, {"name": "s", "sequences": ["c", "d"]}]})", "declared twice");
  expect_bad_input("edge.json", R"({"format": "surfcap.graph_config/1",
    "spaces": [{"name": "s", "sequences": ["a", "b"]}], "transitions": [{"from": "s", "to": "t"}]})",
                   "names an unknown space");
  expect_bad_input("missing.json", R"({"format": "surfcap.graph_config/1", "spaces": [{"name": "s"}]})",
                   "malformed graph config");
}

TEST(GraphFile, CollectsEverySpaceInConfigOrder) {
  surfcap::testing::TemporaryDirectory directory("graph_file_order");
  GraphConfig config = two_spaces("b", "a");
  config.transitions = {{"b", "a"}};
  write_space_file(directory.path(), "a", 1);
  write_space_file(directory.path(), "b", 2);
  ASSERT_TRUE(write_graph(directory.path(), config, {{"test", true}}));
  const core::Json graph = core::read_json_document(directory / "graph.json", "graph", 1);
  ASSERT_EQ(graph["spaces"].size(), 2u);
  EXPECT_EQ(graph["spaces"][0]["name"], "b");
  EXPECT_EQ(graph["spaces"][0]["marker"], 2);
  EXPECT_EQ(graph["spaces"][1]["marker"], 1);
  EXPECT_EQ(graph["transitions"], core::Json::parse(R"([{"from": "b", "to": "a"}])"));
  EXPECT_EQ(graph["provenance"]["test"], true);
  EXPECT_EQ(surfcap::testing::count_hidden_files(directory.path()), 0);
}

TEST(GraphFile, WaitsForEveryShard) {
  surfcap::testing::TemporaryDirectory directory("graph_file_shards");
  const GraphConfig config = two_spaces("a", "b");
  write_space_file(directory.path(), "a", 1);
  EXPECT_FALSE(write_graph(directory.path(), config, {}));
  EXPECT_FALSE(std::filesystem::exists(directory / "graph.json"));
}

}  // namespace
}  // namespace surfcap::graph
