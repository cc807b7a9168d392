#include "surfcap/align/pairwise_alignment.hpp"

#include <gtest/gtest.h>

#include <set>

#include "deformable_shape.hpp"
#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/align/surface_patches.hpp"
#include "surfcap/align/tree_alignment.hpp"

namespace surfcap::align {
namespace {

TEST(SurfacePatches, CoverEverySurfaceVertexWithConnectedDeterministicPatches) {
  const core::Mesh shape = testing::ellipsoid(16, 32);
  const PatchSet patches = surface_patches(shape.V, shape.F, 30);
  ASSERT_EQ(patches.count(), 30);
  long total = 0;
  for (const auto& members : patches.vertices) {
    EXPECT_FALSE(members.empty());
    total += static_cast<long>(members.size());
  }
  EXPECT_EQ(total, shape.V.rows());
  for (long v = 0; v < shape.V.rows(); ++v) EXPECT_GE(patches.label[static_cast<std::size_t>(v)], 0);
  EXPECT_EQ(surface_patches(shape.V, shape.F, 30).label, patches.label);
  const auto hierarchy = patch_hierarchy(shape.V, shape.F, 30, 3);
  ASSERT_EQ(hierarchy.size(), 3u);
  EXPECT_EQ(hierarchy[1].count(), 60);
  EXPECT_EQ(hierarchy[2].count(), 120);
}

TEST(RigidIcp, RecoversASmallRigidMotionOfAnAsymmetricShape) {
  const core::Mesh shape = testing::ellipsoid(20, 40);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.15, Eigen::Vector3d(0.3, 1, 0.1).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.03, -0.02, 0.04);
  const Eigen::MatrixXd moved = ((shape.V * R.transpose()).rowwise() + t.transpose()).eval();
  const geometry::SurfaceQuery target(moved, shape.F);
  const core::Mesh source = testing::ellipsoid(14, 28);  // other connectivity
  IcpOptions options;
  options.iterations = 30;
  options.max_distance = 0.3;
  const RigidFit fit = fit_rigid(source.V, core::vertex_normals(source.V, source.F), target, options);
  EXPECT_LT((fit.rotation - R).norm(), 0.02);
  EXPECT_LT((fit.translation - t).norm(), 0.01);
}

TEST(PairwiseAlignment, FollowsABendAndTwistOntoADifferentTessellation) {
  const core::Mesh template_mesh = testing::ellipsoid(18, 36);
  const PairwiseOptions options;
  const AlignmentTemplate model(template_mesh, options);
  const double bend = 0.3, twist = 0.2;
  const Eigen::Vector3d move(0.05, 0.02, -0.04);
  const core::Mesh target_rest = testing::ellipsoid(23, 44);
  const Eigen::MatrixXd target_V = testing::deform_points(target_rest.V, bend, twist, move);
  const geometry::SurfaceQuery target(target_V, target_rest.F);
  const PairwiseResult result = align_pair(model, model.deformer().rest(), target, options);
  const Eigen::MatrixXd truth = testing::deform_points(template_mesh.V, bend, twist, move);
  const Eigen::VectorXd errors = (result.positions.topRows(template_mesh.V.rows()) - truth).rowwise().norm();
  const double rms = std::sqrt(errors.squaredNorm() / static_cast<double>(errors.size()));
  const double height = model.height();
  // Before alignment the template is far from the truth (rigid motion + bend); afterwards it lies on
  // the target surface and most of the deformation is recovered. What is left is sliding along the
  // smooth surface, which geometry alone cannot see (hence the photometric cues of the paper).
  const double before = std::sqrt((template_mesh.V - truth).rowwise().squaredNorm().mean());
  EXPECT_GT(before, 0.05 * height);
  EXPECT_LT(rms, 0.3 * before) << "rms " << rms << " max " << errors.maxCoeff() << " before " << before;
  EXPECT_LT(rms, 0.025 * height);
  EXPECT_LT(result.mean_residual, 0.002 * height);
  EXPECT_LT(result.uncovered_fraction, 0.01);  // two-sided: the whole target is covered
  EXPECT_GT(result.accepted_patches, result.total_patches / 2);
  EXPECT_GT(result.dense_constraints, template_mesh.V.rows() * 9 / 10);
}

TEST(TreeAlignment, RootMotionRecoversCentroidAndHeading) {
  const core::Mesh shape = testing::ellipsoid(12, 24);
  const double heading = 0.8;
  core::RootMotion truth{0.3, 0.1, -0.7, heading};
  const Eigen::MatrixXd centred = shape.V.rowwise() - shape.V.colwise().mean();
  const Eigen::MatrixXd world = core::to_world(centred, truth);
  const core::RootMotion found = root_motion(shape.V, world);
  EXPECT_NEAR(found.x, truth.x, 1e-9);
  EXPECT_NEAR(found.y, truth.y, 1e-9);
  EXPECT_NEAR(found.z, truth.z, 1e-9);
  EXPECT_NEAR(found.heading, heading, 1e-9);
  EXPECT_LT((core::to_centred(world, found) - centred).norm(), 1e-9);
}

}  // namespace
}  // namespace surfcap::align
