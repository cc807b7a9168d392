#include "surfcap/geometry/tetrahedral_laplacian.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

/// The winding number of a closed mesh about p (Van Oosterom and Strackee's solid angles): 1
/// inside, 0 outside.
double winding_number(const core::Mesh& mesh, const Eigen::Vector3d& p) {
  double total = 0;
  for (long f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)).transpose() - p, b = mesh.V.row(mesh.F(f, 1)).transpose() - p,
                          c = mesh.V.row(mesh.F(f, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return total / (4 * M_PI);
}

core::Mesh concatenated(const core::Mesh& a, const core::Mesh& b) {
  core::Mesh both;
  both.V.resize(a.V.rows() + b.V.rows(), 3);
  both.V << a.V, b.V;
  both.F.resize(a.F.rows() + b.F.rows(), 3);
  both.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return both;
}

TEST(TetrahedralLaplacian, TetrahedralisedSphereKeepsItsSurfaceAndVolume) {
  const core::Mesh sphere = testing::make_sphere(12, 24, 0.5);
  const TetMesh tets = tetrahedralise(sphere.V, sphere.F);
  EXPECT_EQ(tets.surface_vertices, sphere.V.rows());
  ASSERT_GE(tets.V.rows(), sphere.V.rows());
  EXPECT_TRUE(tets.V.topRows(sphere.V.rows()).isApprox(sphere.V));
  const Eigen::VectorXd volumes = tet_volumes(tets.V, tets.T);
  EXPECT_GT(volumes.minCoeff(), 0.0);  // positively oriented
  const double enclosed = testing::signed_volume(sphere);
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
  const core::Mesh both = concatenated(a, b);
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

/// A thin square pyramid from a base centred at `base` (half-width `half`, in the y = base.y plane)
/// to `apex`: a finger with a sharp tip. Faces counter-clockwise seen from outside.
core::Mesh pyramid(const Eigen::Vector3d& base, double half, const Eigen::Vector3d& apex) {
  core::Mesh mesh;
  mesh.V.resize(5, 3);
  mesh.V << base.x() - half, base.y(), base.z() - half, base.x() + half, base.y(), base.z() - half, base.x() + half,
      base.y(), base.z() + half, base.x() - half, base.y(), base.z() + half, apex.x(), apex.y(), apex.z();
  mesh.F.resize(6, 3);
  mesh.F << 0, 1, 2, 0, 2, 3, 0, 4, 1, 1, 4, 2, 2, 4, 3, 3, 4, 0;
  const Eigen::Vector3d centre = mesh.V.colwise().mean().transpose();
  for (long f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    if ((b - a).cross(c - a).dot((a + b + c) / 3 - centre) < 0) std::swap(mesh.F(f, 1), mesh.F(f, 2));
  }
  return mesh;
}

TEST(TetrahedralLaplacian, NoPhantomVolumeGrowsOffSharpTips) {
  // Two fingers spread in a V: grid points between and beside their tips lie outside, closest to
  // a tip whose faces' normals point every way. No interior point and no tet may lie outside, nor
  // hold more than the enclosed volume (a Delaunay tetrahedralisation does not follow so coarse
  // a surface: it holds less).
  const core::Mesh fingers = concatenated(pyramid({-0.15, 0, 0}, 0.05, {-0.5, 1, 0}),
                                          pyramid({0.15, 0, 0}, 0.05, {0.5, 1, 0}));
  const TetMesh tets = tetrahedralise(fingers.V, fingers.F, {.interior_spacing_edges = 0.02});
  ASSERT_GT(tets.V.rows(), tets.surface_vertices + 20);  // the fingers hold interior points
  for (long i = tets.surface_vertices; i < tets.V.rows(); ++i)
    EXPECT_GT(winding_number(fingers, tets.V.row(i).transpose()), 0.5) << "interior point " << i << " is outside";
  long outside = 0;
  for (long t = 0; t < tets.T.rows(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int c = 0; c < 4; ++c) centroid += tets.V.row(tets.T(t, c)).transpose() / 4.0;
    outside += winding_number(fingers, centroid) < 0.5;
  }
  EXPECT_EQ(outside, 0);
  EXPECT_LE(tet_volumes(tets.V, tets.T).sum(), testing::signed_volume(fingers));
}

}  // namespace
}  // namespace surfcap::geometry
