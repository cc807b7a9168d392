#include "surfcap/blend/nonlinear_blend.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "procedural_limb.hpp"
#include "surfcap/blend/linear_blend.hpp"

namespace surfcap::blend {
namespace {

double max_distance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).rowwise().norm().maxCoeff(); }

/// Distance of the shapes with their centroids removed (the blend places the centroid linearly).
double shape_distance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return max_distance(a.rowwise() - a.colwise().mean(), b.rowwise() - b.colwise().mean());
}

/// Length of the tube's axis: distance between the centroids of its first and last rings.
double axis_span(const Eigen::MatrixXd& V, int segments) {
  const Eigen::RowVector3d bottom = V.topRows(segments).colwise().mean();
  const Eigen::RowVector3d top = V.bottomRows(segments).colwise().mean();
  return (top - bottom).norm();
}

TEST(LinearBlend, IsTheNormalisedWeightedAverage) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(10, 3), b = Eigen::MatrixXd::Random(10, 3);
  const Eigen::MatrixXd blended = linear_blend({&a, &b}, {1.0, 3.0});
  EXPECT_LT(max_distance(blended, 0.25 * a + 0.75 * b), 1e-15);
}

TEST(NonlinearBlend, ReproducesTheSourcesAtUnitWeights) {
  const core::Mesh tube = testing::make_tube();
  const NonlinearBlender blender(tube);
  const Eigen::MatrixXd a = testing::pose_tube(tube, 1.4, 0.0), b = testing::pose_tube(tube, -1.4, 1.5);
  EXPECT_LT(max_distance(blender.blend_meshes({&a, &b}, {1.0, 0.0}), a), 1e-9);
  EXPECT_LT(max_distance(blender.blend_meshes({&a, &b}, {0.0, 2.0}), b), 1e-9);
}

TEST(NonlinearBlend, BlendsARigidRotationByTheInterpolatedAngle) {
  const core::Mesh tube = testing::make_tube();
  const NonlinearBlender blender(tube);
  const Eigen::RowVector3d centre = tube.V.colwise().mean();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.4, Eigen::Vector3d(1, 0, 1).normalized()).toRotationMatrix();
  const Eigen::Matrix3d half = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 0, 1).normalized()).toRotationMatrix();
  const Eigen::MatrixXd centred = tube.V.rowwise() - centre;
  const Eigen::MatrixXd rotated = (centred * R.transpose()).rowwise() + centre;
  const Eigen::MatrixXd expected = (centred * half.transpose()).rowwise() + centre;
  EXPECT_LT(max_distance(blender.blend_meshes({&tube.V, &rotated}, {0.75, 0.25}), expected), 1e-9);
}

TEST(NonlinearBlend, KeepsTheLimbLengthWhereLinearBlendShrinksIt) {
  const core::Mesh tube = testing::make_tube();
  const NonlinearBlender blender(tube);
  const Eigen::MatrixXd a = testing::pose_tube(tube, 1.4, 0.0), b = testing::pose_tube(tube, -1.4, 0.0);
  const double rest = axis_span(tube.V, 12);
  const Eigen::MatrixXd nonlinear = blender.blend_meshes({&a, &b}, {0.5, 0.5});
  const Eigen::MatrixXd linear = linear_blend({&a, &b}, {0.5, 0.5});
  // Halfway between ±80° bends is the straight limb: the exact blend finds it.
  // (The sharp procedural joint shears its triangles, so the averaged stretch is not exactly
  // the identity there: a few centimetres, against decimetres for the linear blend.)
  EXPECT_LT(shape_distance(nonlinear, tube.V), 0.04);
  EXPECT_GT(shape_distance(linear, tube.V), 5 * shape_distance(nonlinear, tube.V));
  EXPECT_NEAR(axis_span(nonlinear, 12), rest, 0.03 * rest);
  EXPECT_LT(axis_span(linear, 12), 0.85 * rest);
  std::cout << "straightened limb: exact " << shape_distance(nonlinear, tube.V) << " m, linear "
            << shape_distance(linear, tube.V) << " m; span " << axis_span(nonlinear, 12) << " / "
            << axis_span(linear, 12) << " of " << rest << "\n";
}

TEST(NonlinearBlend, IteratedPairwiseBlendOfThreeSourcesIsSymmetricInOrder) {
  const core::Mesh tube = testing::make_tube(16, 10);
  const NonlinearBlender blender(tube);
  const Eigen::MatrixXd a = testing::pose_tube(tube, 0.6, 0.0), b = testing::pose_tube(tube, 0.9, 0.0),
                        c = testing::pose_tube(tube, 1.2, 0.0);
  // Bends about one axis commute: the order of the pairwise blends must not matter, and the
  // result is the bend by the weighted mean angle.
  const Eigen::MatrixXd abc = blender.blend_meshes({&a, &b, &c}, {0.2, 0.3, 0.5});
  const Eigen::MatrixXd cba = blender.blend_meshes({&c, &b, &a}, {0.5, 0.3, 0.2});
  EXPECT_LT(max_distance(abc, cba), 1e-6);
  const Eigen::MatrixXd mean_bend = testing::pose_tube(tube, 0.2 * 0.6 + 0.3 * 0.9 + 0.5 * 1.2, 0.0);
  EXPECT_LT(shape_distance(abc, mean_bend), 0.01);
}

}  // namespace
}  // namespace surfcap::blend
