#include "surfcap/blend/hybrid_blend.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "procedural_limb.hpp"

namespace surfcap::blend {
namespace {

/// Two (or four) limb "sequences" of three frames whose poses differ by large rotations.
std::vector<std::vector<Eigen::MatrixXd>> limb_sequences(const core::Mesh& tube, int count, double bend_amplitude = 1.3) {
  std::vector<std::vector<Eigen::MatrixXd>> sources(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
    for (int t = 0; t < 3; ++t) {
      const double bend = (i % 2 == 0 ? bend_amplitude : -bend_amplitude) + 0.2 * t;
      const double twist = (i / 2 == 0 ? 0.0 : 1.2) + 0.1 * t;
      sources[static_cast<std::size_t>(i)].push_back(testing::pose_tube(tube, bend, twist));
    }
  return sources;
}

double max_distance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).rowwise().norm().maxCoeff(); }

class HybridBlendTest : public ::testing::Test {
 protected:
  core::Mesh tube = testing::make_tube(20, 10);
  NonlinearBlender blender{tube};
};

TEST_F(HybridBlendTest, CornerWeightsAreMultilinear) {
  const std::vector<double> w = corner_weights({0.25, 0.5});
  ASSERT_EQ(w.size(), 4u);
  EXPECT_DOUBLE_EQ(w[0], 0.375);
  EXPECT_DOUBLE_EQ(w[1], 0.125);
  EXPECT_DOUBLE_EQ(w[2], 0.375);
  EXPECT_DOUBLE_EQ(w[3], 0.125);
}

TEST_F(HybridBlendTest, IsExactAtTheReferenceWeightsUpToStorage) {
  const SourceSet sources(blender, limb_sequences(tube, 2));
  HybridOptions options;
  options.tolerance_m = 0.002;
  const HybridBlend hybrid = HybridBlend::with_breakpoints(sources, {{0.5}}, options);
  ASSERT_EQ(hybrid.reference_count(), 1);
  for (int t = 0; t < sources.frame_count(); ++t) {
    // Only entries below ε·fraction are dropped, and float16 rounding is ~1e-4 of a ≤ 0.5 m value.
    EXPECT_LT(max_distance(hybrid.evaluate(sources, t, {0.5}), sources.exact(t, {0.5})),
              options.tolerance_m * options.sparsity_fraction + 3e-4);
    EXPECT_LT(max_distance(hybrid.evaluate(sources, t, {0.0}), sources.frame(0, t)), 1e-12);
    EXPECT_LT(max_distance(hybrid.evaluate(sources, t, {1.0}), sources.frame(1, t)), 1e-12);
  }
}

TEST_F(HybridBlendTest, OneReferenceHasAtMostAThirdOfTheLinearError) {
  const SourceSet sources(blender, limb_sequences(tube, 2));
  const HybridBlend hybrid = HybridBlend::with_breakpoints(sources, {{0.5}}, HybridOptions{});
  double linear_error = 0, hybrid_error = 0;
  for (int t = 0; t < sources.frame_count(); ++t)
    for (double w = 0.05; w < 1.0; w += 0.05) {
      const Eigen::MatrixXd exact = sources.exact(t, {w});
      linear_error = std::max(linear_error, max_distance(sources.linear(t, {w}), exact));
      hybrid_error = std::max(hybrid_error, max_distance(hybrid.evaluate(sources, t, {w}), exact));
    }
  EXPECT_GT(linear_error, 0.05);  // the limb really is hard for linear blending
  EXPECT_LE(hybrid_error, linear_error / 3.0);
}

TEST_F(HybridBlendTest, BisectionBoundsTheErrorAtRandomWeights) {
  const SourceSet sources(blender, limb_sequences(tube, 2));
  HybridOptions options;
  options.tolerance_m = 0.005;
  const HybridBlend hybrid = HybridBlend::build(sources, options);
  EXPECT_GE(hybrid.reference_count(), 2);  // one subdivision is not enough for ±75° bends
  EXPECT_LE(hybrid.checked_max_error(), options.tolerance_m);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int sample = 0; sample < 25; ++sample) {
    const double w = uniform(random);
    EXPECT_LE(hybrid.max_error(sources, {w}), options.tolerance_m) << "w = " << w;
  }
}

TEST_F(HybridBlendTest, TwoDimensionalSpaceBoundsTheErrorAtRandomWeights) {
  const core::Mesh coarse = testing::make_tube(12, 8);
  const NonlinearBlender coarse_blender(coarse);
  const SourceSet sources(coarse_blender, limb_sequences(coarse, 4, 0.7));
  ASSERT_EQ(sources.dimensions(), 2);
  HybridOptions options;
  options.tolerance_m = 0.01;
  options.checks_per_interval = 1;
  const HybridBlend hybrid = HybridBlend::build(sources, options);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double worst = 0;
  for (int sample = 0; sample < 12; ++sample) worst = std::max(worst, hybrid.max_error(sources, {uniform(random), uniform(random)}));
  // Midpoint checks only: allow the interpolation error between checked points a little slack.
  EXPECT_LE(worst, 1.5 * options.tolerance_m);
  EXPECT_GT(hybrid.reference_count(), 0);
  std::cout << "2-D space: " << hybrid.reference_count() << " references, " << hybrid.exact_blends() << " exact blends\n";
}

TEST_F(HybridBlendTest, ResultDoesNotDependOnTheThreadCount) {
  const SourceSet sources(blender, limb_sequences(tube, 2));
  HybridOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const HybridBlend a = HybridBlend::build(sources, one), b = HybridBlend::build(sources, two);
  ASSERT_EQ(a.breakpoints(), b.breakpoints());
  for (long node = 0; node < a.node_count(); ++node)
    for (int t = 0; t < a.frame_count(); ++t) {
      EXPECT_EQ(a.displacement(node, t).vertices, b.displacement(node, t).vertices);
      EXPECT_EQ(a.displacement(node, t).values, b.displacement(node, t).values);
    }
}

TEST_F(HybridBlendTest, LooserToleranceStoresLess) {
  const SourceSet sources(blender, limb_sequences(tube, 2));
  HybridOptions tight, loose;
  tight.tolerance_m = 0.002;
  loose.tolerance_m = 0.02;
  const HybridBlend a = HybridBlend::build(sources, tight), b = HybridBlend::build(sources, loose);
  EXPECT_GT(a.memory_bytes(), b.memory_bytes());
  EXPECT_GE(a.reference_count(), b.reference_count());
}

}  // namespace
}  // namespace surfcap::blend
