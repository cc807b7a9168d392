#include "surfcap/geometry/rotation.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace surfcap::geometry {
namespace {

Eigen::Matrix3d rotation_about(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

TEST(Rotation, PolarDecompositionRecoversRotationAndStretch) {
  const Eigen::Matrix3d R = rotation_about({1, 2, 3}, 1.1);
  Eigen::Matrix3d S;
  S << 1.3, 0.2, 0.1, 0.2, 0.8, -0.05, 0.1, -0.05, 1.1;  // symmetric positive definite
  const PolarDecomposition polar = polar_decomposition(R * S);
  EXPECT_LT((polar.rotation - R).norm(), 1e-12);
  EXPECT_LT((polar.stretch - S).norm(), 1e-12);
}

TEST(Rotation, PolarDecompositionOfReflectionKeepsProperRotation) {
  Eigen::Matrix3d A = rotation_about({0, 1, 0}, 0.4);
  A.col(2) = -A.col(2);
  const PolarDecomposition polar = polar_decomposition(A);
  EXPECT_NEAR(polar.rotation.determinant(), 1.0, 1e-12);
  EXPECT_LT((polar.rotation * polar.stretch - A).norm(), 1e-12);
  EXPECT_LT((polar.stretch - polar.stretch.transpose()).norm(), 1e-14);
}

TEST(Rotation, QuaternionRoundTrip) {
  const Eigen::Matrix3d R = rotation_about({-1, 0.5, 2}, 2.9);
  const Eigen::Quaterniond q = to_quaternion(R);
  EXPECT_GE(q.w(), 0.0);
  EXPECT_LT((to_rotation_matrix(q) - R).norm(), 1e-12);
}

TEST(Rotation, SlerpFollowsTheShortestArcAtConstantSpeed) {
  const Eigen::Vector3d axis(0, 0, 1);
  const Eigen::Quaterniond a = to_quaternion(Eigen::Matrix3d::Identity());
  Eigen::Quaterniond b = to_quaternion(rotation_about(axis, 2.0));
  b.coeffs() = -b.coeffs();  // same rotation, other hemisphere
  for (double t : {0.0, 0.25, 0.5, 1.0}) {
    const Eigen::Matrix3d expected = rotation_about(axis, 2.0 * t);
    EXPECT_LT((to_rotation_matrix(slerp(a, b, t)) - expected).norm(), 1e-12) << t;
  }
}

TEST(Rotation, InterpolateSeparatesRotationFromScale) {
  const Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d b = 3.0 * rotation_about({0, 1, 0}, M_PI / 2);
  const Eigen::Matrix3d half = interpolate_transform(a, b, 0.5);
  // Rotation by 45° and scale 2, where the linear average would shrink to |(I + 3R)/2|.
  EXPECT_LT((half - 2.0 * rotation_about({0, 1, 0}, M_PI / 4)).norm(), 1e-12);
  EXPECT_LT((lerp(a, 3 * a, 0.25) - 1.5 * a).norm(), 1e-15);
}

}  // namespace
}  // namespace surfcap::geometry
