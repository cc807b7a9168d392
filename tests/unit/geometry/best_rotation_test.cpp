#include "surfcap/geometry/best_rotation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>

namespace surfcap::geometry {
namespace {

/// The reference: Kabsch through the SVD, reflections excluded.
Eigen::Matrix3d kabsch(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

Eigen::Matrix3d random_rotation(std::mt19937& random) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(random), normal(random), normal(random), normal(random));
  return q.normalized().toRotationMatrix();
}

/// U·diag(s)·Vᵀ with random rotations U, V.
Eigen::Matrix3d with_singular_values(std::mt19937& random, const Eigen::Vector3d& s) {
  return random_rotation(random) * s.asDiagonal() * random_rotation(random);
}

void expect_kabsch(const Eigen::Matrix3d& M, double tolerance) {
  const Eigen::Matrix3d R = best_rotation(M);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12) << M;
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12) << M;
  EXPECT_LT((R - kabsch(M)).norm(), tolerance) << M;
}

TEST(BestRotation, MatchesKabschOnWellConditionedCovariances) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> scale(0.2, 3.0);
  for (int trial = 0; trial < 200; ++trial)
    expect_kabsch(with_singular_values(random, {scale(random), scale(random), scale(random)}), 1e-12);
}

TEST(BestRotation, MatchesKabschOnIllConditionedCovariances) {
  // Sliver elements: singular values over ten orders of magnitude.
  std::mt19937 random(11);
  for (int trial = 0; trial < 100; ++trial) {
    const double small = std::pow(10.0, -1.0 - trial % 9);
    // Relative accuracy of the reference itself degrades as 1/σ₃.
    expect_kabsch(with_singular_values(random, {1.0, 0.5, small}), 1e-13 / small);
  }
}

TEST(BestRotation, FlatElementsGetKabschsCorrectionForEitherOrientation) {
  // Rank 2 (a triangle's gradients span its plane): the third axis follows from the first two,
  // for both signs of det(UVᵀ).
  std::mt19937 random(3);
  std::uniform_real_distribution<double> scale(0.2, 3.0);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix3d M = with_singular_values(random, {scale(random), scale(random), 0.0});
    if (trial % 2 == 1) M.col(0) = -M.col(0);  // the other orientation
    expect_kabsch(M, 1e-11);
  }
}

TEST(BestRotation, ReflectionsAndDegenerateCovariancesFallBackToTheSvd) {
  std::mt19937 random(5);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix3d M = with_singular_values(random, {2.0, 1.0, 0.5});
    M.col(1) = -M.col(1);  // det < 0: an inverted element
    expect_kabsch(M, 1e-12);
  }
  const Eigen::Matrix3d rank_one = Eigen::Vector3d(1, 2, 3) * Eigen::RowVector3d(0.5, -1, 2);
  EXPECT_NEAR(best_rotation(rank_one).determinant(), 1.0, 1e-12);
  EXPECT_LT((best_rotation(Eigen::Matrix3d::Zero()) - Eigen::Matrix3d::Identity()).norm(), 1e-15);
}

}  // namespace
}  // namespace surfcap::geometry
