#include "surfcap/graph/transition_similarity.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "surfcap/core/error.hpp"
#include "synthetic_space.hpp"

namespace {

using namespace surfcap;

/// d of casas2013 §3.2.1 computed directly from the reference meshes (no Gram form).
double direct_distance(const blend::StoredSpace& a, long row, const blend::StoredSpace& b, long col, double lambda) {
  const graph::FeatureMatrix fa = graph::reference_features(a, lambda, 1), fb = graph::reference_features(b, lambda, 1);
  return (fa.row(row) - fb.row(col)).squaredNorm() / static_cast<double>(a.vertex_count());
}

TEST(TransitionSimilarity, FeaturesAreTheReferenceMeshesInTheBodyFrame) {
  const auto space = surfcap::testing::synthetic_space("walk", 40, 8, true, 1);
  const graph::FeatureMatrix features = graph::reference_features(space, 1.0, 1);
  ASSERT_EQ(features.rows(), 3 * 8);
  ASSERT_EQ(features.cols(), 6 * 40);
  // Node 1 (u = 0.5) at frame 3: the mean of the sources plus the stored displacement, raised by
  // the blended root height.
  const Eigen::MatrixXd mesh = graph::reference_frame(space, 1, 3);
  const double height = 0.5 * (space.root_motion[3 * 4 + 1] + space.root_motion[(8 + 3) * 4 + 1]);
  for (long v = 0; v < 40; ++v) {
    double expected[3];
    for (int c = 0; c < 3; ++c) {
      expected[c] = 0.5 * (space.references[(3 * 40 + v) * 3 + c] + space.references[((8 + 3) * 40 + v) * 3 + c]);
      if (v < 20) expected[c] += core::half_to_float(space.displacement_values[((3) * 20 + v) * 3 + c]);
      EXPECT_NEAR(mesh(v, c), expected[c], 1e-6);
    }
    EXPECT_NEAR(features(8 + 3, v * 3 + 1), expected[1] + height, 1e-6);
  }
  // Velocity of node 0 at frame 2 in metres per captured frame (T − 1 normalised frames span T − 1
  // captured frames here): the mesh difference plus the root's 0.04 m/frame along +x.
  const Eigen::MatrixXd now = graph::reference_frame(space, 0, 2);
  const Eigen::MatrixXd before = graph::reference_frame(space, 0, 1);
  EXPECT_NEAR(features(2, 3 * 40 + 0), now(0, 0) - before(0, 0) + 0.04, 1e-5);
  EXPECT_NEAR(features(2, 3 * 40 + 2), now(0, 2) - before(0, 2), 1e-5);
}

TEST(TransitionSimilarity, GramFormMatchesTheDirectDistanceAndIsNormalised) {
  const auto a = surfcap::testing::synthetic_space("walk", 60, 7, true, 2);
  const auto b = surfcap::testing::synthetic_space("jump", 60, 5, false, 3, 0.0, 0.02);
  graph::TransitionOptions options;
  options.velocity_weight = 2.0;
  options.threads = 1;
  const graph::TransitionSimilarity s = graph::transition_similarity(a, b, options);
  ASSERT_EQ(s.rows, 21);
  ASSERT_EQ(s.cols, 15);
  float low = 1, high = 0;
  for (float value : s.similarity) {
    low = std::min(low, value);
    high = std::max(high, value);
  }
  EXPECT_NEAR(low, 0.0f, 1e-6);  // the farthest pair defines max d
  EXPECT_LE(high, 1.0f);
  for (auto [row, col] : {std::pair<long, long>{0, 0}, {5, 14}, {20, 7}, {13, 3}}) {
    const double d = direct_distance(a, row, b, col, 2.0);
    EXPECT_NEAR(s.similarity[row * s.cols + col], 1.0 - d / s.max_distance, 1e-5) << row << "," << col;
  }
}

TEST(TransitionSimilarity, ASpaceIsMostSimilarToItselfAndThreadsDoNotChangeTheBytes) {
  const auto a = surfcap::testing::synthetic_space("walk", 50, 6, true, 4);
  graph::TransitionOptions options;
  options.threads = 1;
  const graph::TransitionSimilarity one = graph::transition_similarity(a, a, options);
  for (long i = 0; i < one.rows; ++i) EXPECT_FLOAT_EQ(one.similarity[i * one.cols + i], 1.0f);
  options.threads = 2;
  const graph::TransitionSimilarity two = graph::transition_similarity(a, a, options);
  ASSERT_EQ(one.similarity.size(), two.similarity.size());
  EXPECT_EQ(std::memcmp(one.similarity.data(), two.similarity.data(), one.similarity.size() * sizeof(float)), 0);
}

TEST(TransitionSimilarity, DifferentVertexCountsAreBadInput) {
  const auto a = surfcap::testing::synthetic_space("walk", 50, 6, true, 4);
  const auto b = surfcap::testing::synthetic_space("jump", 40, 6, false, 5);
  try {
    graph::transition_similarity(a, b, {});
    FAIL() << "expected bad_input";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_NE(std::string(e.what()).find("jump"), std::string::npos);
  }
}

}  // namespace
