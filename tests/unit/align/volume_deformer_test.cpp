#include "surfcap/align/volume_deformer.hpp"

#include <gtest/gtest.h>

#include "deformable_shape.hpp"

namespace surfcap::align {
namespace {

Eigen::MatrixXd rigidly_moved(const Eigen::MatrixXd& V) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1, 0.3).normalized()).toRotationMatrix();
  return ((V * R.transpose()).rowwise() + Eigen::RowVector3d(0.4, -0.1, 0.25)).eval();
}

TEST(VolumeDeformer, BuildsATetrahedralModelOfAClosedTemplate) {
  const core::Mesh shape = testing::ellipsoid(12, 24);
  const VolumeDeformer deformer(shape);
  EXPECT_EQ(deformer.model(), "tetrahedral");
  EXPECT_EQ(deformer.surface_vertex_count(), shape.V.rows());
  EXPECT_GE(deformer.vertex_count(), shape.V.rows());
  EXPECT_TRUE(deformer.rest().topRows(shape.V.rows()).isApprox(shape.V));
  EXPECT_NEAR(deformer.rigidity_energy(rigidly_moved(deformer.rest())), 0.0, 1e-10);
  EXPECT_GT(deformer.rigidity_energy(testing::deform_points(deformer.rest(), 0.8, 0.0, Eigen::Vector3d::Zero())), 1e-4);
}

TEST(VolumeDeformer, RigidTargetsOnAFewVerticesMoveTheWholeBodyRigidly) {
  const core::Mesh shape = testing::ellipsoid(12, 24);
  const VolumeDeformer deformer(shape);
  const Eigen::MatrixXd moved = rigidly_moved(deformer.rest());
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(deformer.surface_vertex_count());
  for (long v = 0; v < weights.size(); v += 7) weights(v) = 1.0;
  const auto solver = deformer.factor(weights);
  const Eigen::MatrixXd result =
      deformer.deform(solver, deformer.rest(), moved.topRows(deformer.surface_vertex_count()), weights, 40);
  EXPECT_LT((result - moved).rowwise().norm().maxCoeff(), 1e-3);  // rotation converges from rest
}

TEST(VolumeDeformer, SurfaceModelWhenTetrahedralisationIsOff) {
  const core::Mesh shape = testing::ellipsoid(10, 20);
  DeformerOptions options;
  options.surface_model = true;
  const VolumeDeformer deformer(shape, options);
  EXPECT_NE(deformer.model().find("surface"), std::string::npos);
  EXPECT_EQ(deformer.vertex_count(), shape.V.rows());
  const Eigen::MatrixXd moved = rigidly_moved(shape.V);
  const Eigen::VectorXd weights = Eigen::VectorXd::Constant(shape.V.rows(), 0.5);
  const Eigen::MatrixXd result = deformer.deform(deformer.factor(weights), moved, moved, weights, 3);
  EXPECT_LT((result - moved).rowwise().norm().maxCoeff(), 1e-6);  // a rigid pose is a fixed point
}

}  // namespace
}  // namespace surfcap::align
