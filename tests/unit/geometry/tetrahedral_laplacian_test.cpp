#include "surfcap/geometry/tetrahedral_laplacian.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

TEST(TetrahedralLaplacian, TetrahedralisedSphereKeepsItsSurfaceAndVolume) {
  const core::Mesh sphere = testing::make_sphere(12, 24, 0.5);
  const TetMesh tets = tetrahedralise(sphere.V, sphere.F);
  EXPECT_EQ(tets.surface_vertices, sphere.V.rows());
  ASSERT_GE(tets.V.rows(), sphere.V.rows());
  EXPECT_TRUE(tets.V.topRows(sphere.V.rows()).isApprox(sphere.V));
  const Eigen::VectorXd volumes = tet_volumes(tets.V, tets.T);
  EXPECT_GT(volumes.minCoeff(), 0.0);  // positively oriented
  // The polyhedron's volume, from the divergence theorem over its faces.
  double enclosed = 0;
  for (long f = 0; f < sphere.F.rows(); ++f) {
    const Eigen::Vector3d a = sphere.V.row(sphere.F(f, 0)), b = sphere.V.row(sphere.F(f, 1)),
                          c = sphere.V.row(sphere.F(f, 2));
    enclosed += a.dot(b.cross(c)) / 6.0;
  }
  EXPECT_NEAR(volumes.sum(), enclosed, 0.01 * enclosed);  // slivers are dropped
  EXPECT_NEAR(volumes.sum(), 4.0 / 3.0 * M_PI * 0.125, 0.05 * 4.0 / 3.0 * M_PI * 0.125);
}

TEST(TetrahedralLaplacian, GradientOfCoordinatesIsIdentityAndLaplacianEnergyIsVolume) {
  const core::Mesh sphere = testing::make_sphere(8, 16, 1.0);
  const TetMesh tets = tetrahedralise(sphere.V, sphere.F);
  const Eigen::SparseMatrix<double> G = tetrahedral_gradient_operator(tets.V, tets.T);
  const Eigen::MatrixXd gradients = G * tets.V;
  for (long t = 0; t < tets.T.rows(); ++t) {
    const Eigen::Matrix3d gradient = gradients.block<3, 3>(3 * t, 0);
    EXPECT_TRUE(gradient.isApprox(Eigen::Matrix3d::Identity(), 1e-8)) << "tet " << t;
  }
  const Eigen::SparseMatrix<double> L = tetrahedral_laplacian(tets.V, tets.T);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(tets.V.rows());
  EXPECT_LT((L * ones).norm(), 1e-9);
  EXPECT_LT((Eigen::SparseMatrix<double>(L.transpose()) - L).norm(), 1e-9);
  // A linear function f = a·p has energy fᵀLf = |a|² · volume.
  const Eigen::Vector3d a(0.3, -1.2, 0.5);
  const Eigen::VectorXd f = tets.V * a;
  EXPECT_NEAR(f.dot(L * f), a.squaredNorm() * tet_volumes(tets.V, tets.T).sum(), 1e-8);
}

TEST(TetrahedralLaplacian, GapsBetweenTouchingPartsAreNotFilled) {
  // Two spheres 1 cm apart: no tet may bridge the gap (their centroids lie outside both).
  core::Mesh a = testing::make_sphere(10, 20, 0.5), b = a;
  b.V.col(0).array() += 1.01;
  core::Mesh both;
  both.V.resize(a.V.rows() * 2, 3);
  both.V << a.V, b.V;
  both.F.resize(a.F.rows() * 2, 3);
  both.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  const TetMesh tets = tetrahedralise(both.V, both.F);
  for (long t = 0; t < tets.T.rows(); ++t) {
    bool left = false, right = false;
    for (int c = 0; c < 4; ++c) {
      const double x = tets.V(tets.T(t, c), 0);
      (x < 0.505 ? left : right) = true;
    }
    EXPECT_FALSE(left && right) << "tet " << t << " bridges the gap";
  }
  EXPECT_NEAR(tet_volumes(tets.V, tets.T).sum(), 2 * 4.0 / 3.0 * M_PI * 0.125, 0.1 * 4.0 / 3.0 * M_PI * 0.125);
}

}  // namespace
}  // namespace surfcap::geometry
