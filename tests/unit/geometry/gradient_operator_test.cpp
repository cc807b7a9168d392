#include "surfcap/geometry/gradient_operator.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

/// Textbook cotangent weights: L_ij = −½(cot α + cot β), L_ii = −Σ_j L_ij.
Eigen::MatrixXd cotangent_reference(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(V.rows(), V.rows());
  for (long k = 0; k < F.rows(); ++k)
    for (int c = 0; c < 3; ++c) {
      const int i = F(k, c), j = F(k, (c + 1) % 3), o = F(k, (c + 2) % 3);
      const Eigen::Vector3d a = V.row(i) - V.row(o), b = V.row(j) - V.row(o);
      const double cotangent = a.dot(b) / a.cross(b).norm();
      L(i, j) -= 0.5 * cotangent;
      L(j, i) -= 0.5 * cotangent;
      L(i, i) += 0.5 * cotangent;
      L(j, j) += 0.5 * cotangent;
    }
  return L;
}

TEST(GradientOperator, ConstantsHaveZeroGradient) {
  const core::Mesh sphere = testing::make_sphere(8, 12, 0.7);
  const Eigen::SparseMatrix<double> G = gradient_operator(sphere.V, sphere.F);
  ASSERT_EQ(G.rows(), 3 * sphere.F.rows());
  ASSERT_EQ(G.cols(), sphere.V.rows());
  EXPECT_LT((G * Eigen::VectorXd::Ones(sphere.V.rows())).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(GradientOperator, LinearFunctionHasItsTangentialGradient) {
  const core::Mesh sphere = testing::make_sphere(8, 12, 0.7);
  const Eigen::Vector3d a(0.3, -1.2, 2.0);
  const Eigen::VectorXd f = sphere.V * a;
  const Eigen::VectorXd g = gradient_operator(sphere.V, sphere.F) * f;
  for (long k = 0; k < sphere.F.rows(); ++k) {
    const Eigen::Vector3d p0 = sphere.V.row(sphere.F(k, 0)), p1 = sphere.V.row(sphere.F(k, 1)),
                          p2 = sphere.V.row(sphere.F(k, 2));
    const Eigen::Vector3d cross = (p1 - p0).cross(p2 - p0);
    if (cross.norm() < 1e-12) continue;
    const Eigen::Vector3d n = cross.normalized();
    const Eigen::Vector3d expected = a - n * n.dot(a);
    EXPECT_LT((g.segment<3>(3 * k) - expected).norm(), 1e-10) << "triangle " << k;
  }
}

TEST(GradientOperator, GtAGIsTheCotangentLaplacian) {
  const core::Mesh sphere = testing::make_sphere(6, 9, 1.3);
  const Eigen::MatrixXd L(gradient_laplacian(sphere.V, sphere.F));
  const Eigen::MatrixXd reference = cotangent_reference(sphere.V, sphere.F);
  EXPECT_LT((L - reference).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((L - L.transpose()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(GradientOperator, AreaMatrixSumsToSurfaceArea) {
  const core::Mesh sphere = testing::make_sphere(10, 16, 1.0);
  const Eigen::SparseMatrix<double> A = triangle_area_matrix(sphere.V, sphere.F);
  const double area = Eigen::MatrixXd(A).trace() / 3.0;
  EXPECT_NEAR(area, core::face_areas(sphere.V, sphere.F).sum(), 1e-12);
  EXPECT_NEAR(area, 4 * M_PI, 0.4);  // a coarse sphere is a little smaller
}

}  // namespace
}  // namespace surfcap::geometry
