#include "surfcap/geometry/best_rotation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

namespace surfcap::geometry {
namespace {

Eigen::Matrix3d random_matrix(std::mt19937& random, double spread) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix3d M;
  for (int i = 0; i < 9; ++i) M(i / 3, i % 3) = normal(random);
  // A rotation times a positive stretch of condition up to `spread` (a deformed element).
  const Eigen::Matrix3d rotation = Eigen::Quaterniond(M.col(0).x(), M.col(0).y(), M.col(0).z(), M.col(1).x()).normalized().toRotationMatrix();
  std::uniform_real_distribution<double> scale(1.0, spread);
  Eigen::Matrix3d stretch = M * M.transpose() / 9.0 + Eigen::Matrix3d::Identity();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(stretch);
  stretch = eigen.eigenvectors() * Eigen::Vector3d(1.0, scale(random), scale(random)).asDiagonal() *
            eigen.eigenvectors().transpose();
  return rotation * stretch;
}

TEST(BestRotation, PolarRotationAgreesWithTheSvd) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Matrix3d M = random_matrix(random, trial % 2 == 0 ? 2.0 : 1e4) * (trial % 3 == 0 ? 1e-6 : 3.0);
    const Eigen::Matrix3d expected = best_rotation(M);
    const Eigen::Matrix3d polar = polar_rotation(M);
    EXPECT_LT((polar - expected).cwiseAbs().maxCoeff(), 1e-12) << M;
    EXPECT_LT((polar.transpose() * polar - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_NEAR(polar.determinant(), 1.0, 1e-13);
  }
}

TEST(BestRotation, PolarRotationExcludesReflectionsAndHandlesDegenerateCovariances) {
  std::mt19937 random(11);
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  flip(1, 1) = -1;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d M = random_matrix(random, 3.0) * flip;  // det < 0
    const Eigen::Matrix3d polar = polar_rotation(M);
    EXPECT_LT((polar - best_rotation(M)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(polar.determinant(), 1.0, 1e-12);
  }
  // Rank one (a collapsed element) and zero: still a proper rotation, the SVD's.
  const Eigen::Matrix3d rank_one = Eigen::Vector3d(1, 2, 3) * Eigen::RowVector3d(0.5, -1, 2);
  EXPECT_TRUE(polar_rotation(rank_one).isApprox(best_rotation(rank_one), 1e-12));
  EXPECT_NEAR(polar_rotation(Eigen::Matrix3d::Zero()).determinant(), 1.0, 1e-12);
  // Rank two (a triangle's gradients, both in their planes), with either sign of the third axis.
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d M = random_matrix(random, 3.0);
    const Eigen::Vector3d n = M.col(0).normalized();
    const Eigen::Matrix3d planar = (Eigen::Matrix3d::Identity() - n * n.transpose()) * M * (trial % 2 ? flip : Eigen::Matrix3d::Identity());
    const Eigen::Matrix3d polar = polar_rotation(planar);
    EXPECT_LT((polar - best_rotation(planar)).cwiseAbs().maxCoeff(), 1e-12) << planar;
    EXPECT_NEAR(polar.determinant(), 1.0, 1e-12);
  }
  // A pure rotation is returned as is.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  EXPECT_LT((polar_rotation(R) - R).cwiseAbs().maxCoeff(), 1e-14);
}

}  // namespace
}  // namespace surfcap::geometry
