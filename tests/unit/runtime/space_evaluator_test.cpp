#include "surfcap/runtime/space_evaluator.hpp"

#include <gtest/gtest.h>

#include "surfcap/graph/transition_similarity.hpp"
#include "synthetic_space.hpp"

namespace {

using namespace surfcap;

std::vector<float> evaluate(const runtime::SpaceEvaluator& evaluator, double frame, double u) {
  std::vector<float> out(static_cast<std::size_t>(evaluator.vertex_count() * 3));
  evaluator.evaluate(frame, &u, out.data());
  return out;
}

TEST(SpaceEvaluator, IsExactAtGridNodesAndInterpolatesBetween) {
  const auto space = surfcap::testing::synthetic_space("walk", 30, 8, true, 7);
  const runtime::SpaceEvaluator evaluator(space);
  for (long node = 0; node < 3; ++node)
    for (int t : {0, 3, 7}) {
      const Eigen::MatrixXd expected = graph::reference_frame(space, node, t);
      const std::vector<float> got = evaluate(evaluator, t, space.node_coordinates[node][0]);
      for (long v = 0; v < 30; ++v)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[v * 3 + c], expected(v, c), 1e-5);
    }
  // Inside a cell (u = 0.3: g = 0.4 at node 0, 0.6 at node 1) and between frames 2 and 3.
  const Eigen::MatrixXd a2 = graph::reference_frame(space, 0, 2), b2 = graph::reference_frame(space, 1, 2);
  const Eigen::MatrixXd a3 = graph::reference_frame(space, 0, 3), b3 = graph::reference_frame(space, 1, 3);
  const Eigen::MatrixXd expected = 0.75 * (0.4 * a2 + 0.6 * b2) + 0.25 * (0.4 * a3 + 0.6 * b3);
  const std::vector<float> got = evaluate(evaluator, 2.25, 0.3);
  for (long v = 0; v < 30; ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[v * 3 + c], expected(v, c), 1e-5);
  // Cyclic: the step from the last frame wraps to frame 0.
  const Eigen::MatrixXd last = graph::reference_frame(space, 2, 7), first = graph::reference_frame(space, 2, 0);
  const std::vector<float> wrapped = evaluate(evaluator, 7.5, 1.0);
  for (long v = 0; v < 30; ++v) EXPECT_NEAR(wrapped[v * 3], 0.5 * (last(v, 0) + first(v, 0)), 1e-5);
}

TEST(SpaceEvaluator, CellWeightsAreMultilinearAndSumToOne) {
  const auto space = surfcap::testing::synthetic_space("walk", 10, 4, true, 7);
  const runtime::SpaceEvaluator evaluator(space);
  long nodes[8];
  double weights[8];
  double u = 0.8;
  ASSERT_EQ(evaluator.cell_weights(&u, nodes, weights), 2);
  EXPECT_EQ(nodes[0], 1);
  EXPECT_EQ(nodes[1], 2);
  EXPECT_NEAR(weights[0], 0.4, 1e-12);
  EXPECT_NEAR(weights[1], 0.6, 1e-12);
  u = 1.0;
  ASSERT_EQ(evaluator.cell_weights(&u, nodes, weights), 1);
  EXPECT_EQ(nodes[0], 2);
  EXPECT_NEAR(weights[0], 1.0, 1e-12);
}

TEST(SpaceEvaluator, RootMotionIsTheBlendedTravelAndWrapsCycles) {
  const auto space = surfcap::testing::synthetic_space("walk", 10, 8, true, 7, 0.04, 0.08);
  const runtime::SpaceEvaluator evaluator(space);
  double u = 0.5;
  const Eigen::Vector3d step = evaluator.root_step(1.0, 3.5, &u);
  EXPECT_NEAR(step(0), 2.5 * 0.06, 1e-6);  // blended 0.06 m per frame along +x
  EXPECT_NEAR(step(1), 0.0, 1e-9);
  EXPECT_NEAR(step(2), 0.0, 1e-9);
  // Across the cycle end (T = 8: 6 → 1 is 3 frames), the travel keeps its pace.
  EXPECT_NEAR(evaluator.root_step(6.0, 1.0, &u)(0), 3 * 0.06, 1e-6);
  EXPECT_NEAR(evaluator.root_height(0.0, &u), 0.9, 1e-6);
  // One output frame advances T−1 frames per (T−1)/25 s at 25 fps: one normalised frame.
  EXPECT_NEAR(evaluator.frames_per_step(&u, 25.0), 1.0, 1e-9);
}

}  // namespace
