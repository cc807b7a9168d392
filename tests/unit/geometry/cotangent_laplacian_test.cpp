#include "surfcap/geometry/cotangent_laplacian.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

TEST(CotangentLaplacian, SymmetricKillsConstantsAndRigidMotions) {
  const core::Mesh sphere = testing::make_sphere(12, 16, 0.5);
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(sphere.V, sphere.F);
  EXPECT_LT((Eigen::MatrixXd(L) - Eigen::MatrixXd(L.transpose())).norm(), 1e-12);
  EXPECT_LT((L * Eigen::VectorXd::Ones(L.rows())).norm(), 1e-10);
  // Energy xᵀLx ≥ 0 and a rigid motion keeps the differential coordinates' lengths.
  const Eigen::MatrixXd delta = L * sphere.V;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::MatrixXd moved = (sphere.V * R.transpose()).rowwise() + Eigen::RowVector3d(1, -2, 0.5);
  const Eigen::MatrixXd moved_delta = L * moved;  // L of the rest shape applied to the moved shape
  EXPECT_LT((moved_delta - delta * R.transpose()).norm(), 1e-10);
  for (int c = 0; c < 3; ++c) EXPECT_GE(sphere.V.col(c).dot(L * sphere.V.col(c)), 0);
}

TEST(CotangentLaplacian, LinearFunctionsAreHarmonicInsideAPlanarGrid) {
  // Irregular planar grid: δ of interior vertices vanishes for any linear function.
  const int k = 6;
  Eigen::MatrixXd V((k + 1) * (k + 1), 3);
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j <= k; ++j)
      V.row(i * (k + 1) + j) << i + 0.2 * std::sin(3.0 * j), j + 0.2 * std::cos(2.0 * i), 0;
  Eigen::MatrixXi F(2 * k * k, 3);
  int f = 0;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const int a = i * (k + 1) + j, b = a + 1, c = a + k + 1, d = c + 1;
      F.row(f++) << a, c, b;
      F.row(f++) << b, c, d;
    }
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(V, F);
  const Eigen::VectorXd linear = 2 * V.col(0) - 3 * V.col(1) + Eigen::VectorXd::Constant(V.rows(), 4);
  const Eigen::VectorXd delta = L * linear;
  for (int i = 1; i < k; ++i)
    for (int j = 1; j < k; ++j) EXPECT_NEAR(delta[i * (k + 1) + j], 0, 1e-10);
  // The known value: a unit right-angle triangle fan gives weight ½(cot 45° + cot 45°) = 1.
  EXPECT_GT(L.diagonal().minCoeff(), 0);
}

}  // namespace
}  // namespace surfcap::geometry
