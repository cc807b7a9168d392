#include "surfcap/blend/time_warp.hpp"

#include <gtest/gtest.h>

#include "procedural_limb.hpp"

namespace surfcap::blend {
namespace {

TEST(TimeWarp, DtwOfIdenticalSequencesIsTheDiagonal) {
  Eigen::MatrixXd cost = Eigen::MatrixXd::Ones(5, 5);
  cost.diagonal().setZero();
  const auto path = dynamic_time_warp(cost);
  ASSERT_EQ(path.size(), 5u);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(path[k], std::make_pair(k, k));
}

TEST(TimeWarp, RecoversATimeStretch) {
  // The same bending motion at two speeds: 11 frames vs 21 frames.
  const core::Mesh tube = testing::make_tube(10, 6);
  std::vector<Eigen::MatrixXd> slow, fast;
  for (int k = 0; k <= 20; ++k) slow.push_back(testing::pose_tube(tube, 1.2 * k / 20.0, 0.0));
  for (int k = 0; k <= 10; ++k) fast.push_back(testing::pose_tube(tube, 1.2 * k / 10.0, 0.0));
  const auto warps = time_warps({fast, slow}, 11);
  ASSERT_EQ(warps.size(), 2u);
  for (int k = 0; k <= 10; ++k) {
    EXPECT_NEAR(warps[0][k], k, 1e-12);
    EXPECT_NEAR(warps[1][k], 2.0 * k, 0.51) << k;  // DTW matches slow frame 2k to fast frame k
    if (k > 0) EXPECT_GE(warps[1][k], warps[1][k - 1]);
  }
  EXPECT_DOUBLE_EQ(warps[1].front(), 0.0);
  EXPECT_DOUBLE_EQ(warps[1].back(), 20.0);
}

TEST(TimeWarp, SamplesFramesAndRootsLinearly) {
  const std::vector<Eigen::MatrixXd> frames{Eigen::MatrixXd::Zero(2, 3), Eigen::MatrixXd::Ones(2, 3)};
  EXPECT_DOUBLE_EQ(sample_frame(frames, 0.25)(1, 2), 0.25);
  const std::vector<core::RootMotion> roots{{0, 1, 0, 3.0}, {1, 1, 2, -3.0}};
  const core::RootMotion half = sample_root(roots, 0.5);
  EXPECT_DOUBLE_EQ(half.x, 0.5);
  EXPECT_DOUBLE_EQ(half.z, 1.0);
  // 3 → −3 rad is a short turn through π, not a long one through 0.
  EXPECT_NEAR(half.heading, 3.0 + 0.5 * (2 * M_PI - 6.0), 1e-12);
}

}  // namespace
}  // namespace surfcap::blend
