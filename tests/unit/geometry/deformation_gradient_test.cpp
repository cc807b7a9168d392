#include "surfcap/geometry/deformation_gradient.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

TEST(DeformationGradient, SimilarityTransformIsRecoveredExactly) {
  const core::Mesh sphere = testing::make_sphere(6, 10, 0.5);
  const Eigen::Matrix3d M = 1.7 * Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const Eigen::RowVector3d shift(0.3, -2, 5);
  const Eigen::MatrixXd deformed = (sphere.V * M.transpose()).rowwise() + shift;
  for (const Eigen::Matrix3d& T : deformation_gradients(sphere.V, sphere.F, deformed))
    EXPECT_LT((T - M).norm(), 1e-10);
}

TEST(DeformationGradient, MapsRestEdgesToDeformedEdges) {
  const core::Mesh sphere = testing::make_sphere(6, 10, 0.5);
  Eigen::Matrix3d M;
  M << 1.2, 0.3, 0.0, -0.1, 0.7, 0.4, 0.2, 0.0, 1.5;  // general affine map: shear + anisotropic scale
  const Eigen::MatrixXd deformed = sphere.V * M.transpose();
  const DeformationGradient gradient(sphere.V, sphere.F);
  for (long k = 0; k < sphere.F.rows(); ++k) {
    const Eigen::Matrix3d T = gradient.triangle(deformed, k);
    for (int c = 1; c < 3; ++c) {
      const Eigen::Vector3d rest_edge = sphere.V.row(sphere.F(k, c)) - sphere.V.row(sphere.F(k, 0));
      const Eigen::Vector3d edge = deformed.row(sphere.F(k, c)) - deformed.row(sphere.F(k, 0));
      EXPECT_LT((T * rest_edge - edge).norm(), 1e-10);
    }
  }
}

TEST(DeformationGradient, RestPoseIsIdentity) {
  const core::Mesh sphere = testing::make_sphere(5, 7, 2.0);
  for (const Eigen::Matrix3d& T : deformation_gradients(sphere.V, sphere.F, sphere.V))
    EXPECT_LT((T - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace surfcap::geometry
