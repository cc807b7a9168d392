#include "surfcap/runtime/controller.hpp"

#include <gtest/gtest.h>

#include <random>

#include "surfcap/core/error.hpp"
#include "synthetic_space.hpp"

namespace {

using namespace surfcap;

asset::CharacterTransition random_transition(const std::string& from, long rows, const std::string& to, long cols,
                                             unsigned seed) {
  asset::CharacterTransition transition{from, to, rows, cols, {}};
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (long k = 0; k < rows * cols; ++k) transition.similarity.push_back(uniform(random));
  return transition;
}

asset::Character two_space_character(bool both_ways = true) {
  asset::Character character;
  character.name = "test";
  character.fps = 25;
  character.template_mesh.V = Eigen::MatrixXd::Zero(8, 3);
  character.spaces.push_back(surfcap::testing::synthetic_space("walk", 8, 12, true, 1));
  character.spaces.push_back(surfcap::testing::synthetic_space("jump", 8, 20, false, 2, 0.0, 0.01));
  character.transitions.push_back(random_transition("walk", 36, "jump", 60, 3));
  if (both_ways) character.transitions.push_back(random_transition("jump", 60, "walk", 36, 4));
  return character;
}

void expect_bad_input(const core::Json& script, const asset::Character& character, const std::string& needle) {
  try {
    runtime::parse_control_script(script, "control.json", character);
    FAIL() << "expected bad input: " << needle;
  } catch (const core::Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    const std::string message = e.what();
    EXPECT_NE(message.find("control.json"), std::string::npos) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << message;
  }
}

TEST(ControlScript, UnknownSpacesParametersAndTransitionsAreBadInput) {
  const asset::Character character = two_space_character(false);
  expect_bad_input({{"duration_s", 1}, {"start", {{"space", "swim"}}}}, character, "swim");
  expect_bad_input({{"duration_s", 1}, {"start", {{"space", "walk"}, {"parameters", {{"speed", 1}}}}}}, character, "speed");
  expect_bad_input({{"duration_s", 3},
                    {"start", {{"space", "walk"}}},
                    {"timeline", {{{"time_s", 1}, {"space", "jump"}}, {{"time_s", 2}, {"space", "walk"}}}}},
                   character, "jump → walk");
  expect_bad_input({{"duration_s", 3},
                    {"start", {{"space", "walk"}}},
                    {"timeline", {{{"time_s", 2}, {"space", "walk"}}, {{"time_s", 1}, {"space", "walk"}}}}},
                   character, "decrease");
  expect_bad_input({{"start", {{"space", "walk"}}}}, character, "duration_s");
}

TEST(Controller, PlaysATimelineThroughPlannedTransitionsAndReturnsFromOneShotSpaces) {
  const asset::Character character = two_space_character();
  const core::Json json = {{"fps", 25},
                           {"duration_s", 2.4},
                           {"start", {{"space", "walk"}, {"parameters", {{"u", 0.2}}}}},
                           {"timeline", {{{"time_s", 0.4}, {"space", "jump"}, {"parameters", {{"u", 0.7}}}}}}};
  const runtime::ControlScript script = runtime::parse_control_script(json, "control.json", character);
  runtime::Controller controller(character, script);
  long frames = 0;
  std::vector<int> spaces;
  std::vector<float> expected(8 * 3);
  Eigen::Vector3d previous_root = Eigen::Vector3d::Zero();
  while (!controller.done()) {
    const runtime::FrameState& frame = controller.step();
    EXPECT_EQ(frame.index, frames++);
    // The character moves on continuously, also across transitions (≤ the fastest source's pace).
    EXPECT_LE((frame.root - previous_root).head<1>().norm(), 0.08 * 1.6 + 1e-9) << "frame " << frame.index;
    EXPECT_GE(frame.root(0), previous_root(0) - 1e-9);
    previous_root = frame.root;
    spaces.push_back(frame.state.space);
    // The mesh is the space's hybrid blend at the frame's state, placed by the root motion.
    const runtime::SpaceEvaluator& space = controller.evaluator(frame.state.space);
    space.evaluate(frame.state.frame, frame.weights.data(), expected.data());
    const double c = std::cos(frame.heading), s = std::sin(frame.heading);
    for (int v = 0; v < 8; ++v) {
      ASSERT_FLOAT_EQ(controller.centred_positions()[v * 3], expected[v * 3]);
      EXPECT_NEAR(controller.world_positions()[v * 3],
                  c * expected[v * 3] + s * expected[v * 3 + 2] + frame.root(0), 1e-4);
    }
  }
  EXPECT_EQ(frames, 60);
  ASSERT_EQ(controller.transitions().size(), 2u);
  EXPECT_EQ(controller.transitions()[0].from, "walk");
  EXPECT_EQ(controller.transitions()[0].to, "jump");
  EXPECT_EQ(controller.transitions()[0].frame, 10);
  EXPECT_EQ(controller.transitions()[1].to, "walk");  // automatic return at the end of the jump
  EXPECT_EQ(spaces.front(), 0);
  EXPECT_NE(std::find(spaces.begin(), spaces.end(), 1), spaces.end());
  EXPECT_EQ(spaces.back(), 0);
}

TEST(Controller, WalksToWaypoints) {
  const asset::Character character = two_space_character();
  const core::Json json = {{"fps", 25},
                           {"start", {{"space", "walk"}, {"parameters", {{"u", 1.0}}}}},
                           {"waypoints", {{{"x", 1.0}, {"z", 1.0}}, {{"x", 0.0}, {"z", 2.0}}}},
                           {"turn_rate", 3.0},
                           {"max_duration_s", 30}};
  const runtime::ControlScript script = runtime::parse_control_script(json, "control.json", character);
  runtime::Controller controller(character, script);
  double closest = 1e9;
  while (!controller.done()) {
    const runtime::FrameState& frame = controller.step();
    closest = std::min(closest, std::hypot(frame.root(0), frame.root(2) - 2.0));
  }
  EXPECT_LT(closest, 0.3 + 0.1);  // reached the last waypoint (within the arrival radius + a step)
}

}  // namespace
