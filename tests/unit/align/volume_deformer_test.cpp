#include "surfcap/align/volume_deformer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

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

/// RMS distance of `rows` of `a` to the same rows of `b`.
double rms_on(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, const std::vector<long>& rows) {
  double sum = 0;
  for (const long v : rows) sum += (a.row(v) - b.row(v)).squaredNorm();
  return std::sqrt(sum / static_cast<double>(rows.size()));
}

TEST(VolumeDeformer, TheVolumeUnderUnseenSurfaceFollowsAFlare) {
  // The ellipsoid's lower third unseen (under a skirt); the targets flare it out like a hem after a
  // landing (×1.6 away from the vertical axis, growing downwards) and keep the rest in place.
  const core::Mesh shape = testing::ellipsoid(16, 32);
  const long n = shape.V.rows();
  std::vector<char> unseen(static_cast<std::size_t>(n), 0);
  std::vector<long> lower, upper;
  Eigen::MatrixXd targets = shape.V;
  for (long v = 0; v < n; ++v) {
    const double y = shape.V(v, 1);
    if (y < -0.3) {
      unseen[static_cast<std::size_t>(v)] = 1;
      lower.push_back(v);
      const double flare = 1 + 0.6 * (-0.3 - y) / 0.6;
      targets(v, 0) *= flare;
      targets(v, 2) *= flare;
    } else {
      upper.push_back(v);
    }
  }
  const VolumeDeformer rigid(shape), soft(shape, {}, unseen);
  EXPECT_EQ(rigid.softened_elements(), 0);
  EXPECT_GT(soft.softened_elements(), 0);
  EXPECT_LT(soft.softened_elements(), soft.tetrahedra().rows() / 2);
  const Eigen::VectorXd weights = Eigen::VectorXd::Constant(n, 0.05);
  const auto solve = [&](const VolumeDeformer& deformer) {
    return Eigen::MatrixXd(deformer.deform(deformer.factor(weights), deformer.rest(), targets, weights, 20).topRows(n));
  };
  const Eigen::MatrixXd held = solve(rigid), followed = solve(soft);
  const double flare = rms_on(shape.V, targets, lower);
  // The rigid volume holds a fifth of the flare back (0.22), the soft one a third of that (0.08).
  EXPECT_GT(rms_on(held, targets, lower), 0.15 * flare);
  EXPECT_LT(rms_on(followed, targets, lower), 0.1 * flare);
  EXPECT_LT(rms_on(followed, targets, lower), 0.5 * rms_on(held, targets, lower));
  EXPECT_LT(rms_on(followed, targets, upper), rms_on(held, targets, upper));  // and pulls less on the rest
  // No vertex flagged: the same model as none given, bit for bit.
  const VolumeDeformer all_seen(shape, {}, std::vector<char>(static_cast<std::size_t>(n), 0));
  EXPECT_EQ(all_seen.softened_elements(), 0);
  EXPECT_TRUE(solve(all_seen) == held);
}

/// One mesh of `a` and of `b` moved `dx` along x (two components).
core::Mesh side_by_side(const core::Mesh& a, const core::Mesh& b, double dx) {
  core::Mesh both;
  both.V.resize(a.V.rows() + b.V.rows(), 3);
  both.V << a.V, b.V.rowwise() + Eigen::RowVector3d(dx, 0, 0);
  both.F.resize(a.F.rows() + b.F.rows(), 3);
  both.F << a.F, b.F.array() + static_cast<int>(a.V.rows());
  return both;
}

TEST(VolumeDeformer, PartsTouchingAtRestAreNotGluedTogetherByTheVolume) {
  // Two ellipsoids side by side, pressed 2 cm into each other: parts of one template that touch at
  // rest but are far apart along its surface (a hand on the hip, thighs pressed together).
  const core::Mesh part = testing::ellipsoid(12, 24);
  const long n = part.V.rows();
  const double gap = 2 * testing::ellipsoid_axes().x() - 0.02;
  const core::Mesh pair = side_by_side(part, part, gap);
  const VolumeDeformer deformer(pair);
  EXPECT_EQ(VolumeDeformer(part).cut_elements(), 0);
  EXPECT_GT(deformer.cut_elements(), 0);
  EXPECT_LT(deformer.cut_elements(), deformer.tetrahedra().rows() / 5);
  // The cut's vertices are where the parts press together: on both parts, on their inner halves.
  const std::vector<long>& cut = deformer.cut_vertices();
  ASSERT_FALSE(cut.empty());
  EXPECT_TRUE(std::is_sorted(cut.begin(), cut.end()));
  EXPECT_LT(cut.front(), n);
  EXPECT_GE(cut.back(), n);
  for (const long v : cut) EXPECT_LT(std::abs(pair.V(v, 0) - gap / 2), testing::ellipsoid_axes().x()) << v;
  // The second part pulled 0.3 m away, the first held where it is, by weak targets on every vertex.
  Eigen::MatrixXd targets = pair.V;
  targets.bottomRows(n).col(0).array() += 0.3;
  const Eigen::VectorXd weights = Eigen::VectorXd::Constant(2 * n, 0.05);
  const Eigen::MatrixXd result =
      deformer.deform(deformer.factor(weights), deformer.rest(), targets, weights, 20).topRows(2 * n);
  // Each part is translated onto its targets (to the solver's precision); a volume joining them
  // would drag the first along and hold the second back.
  EXPECT_LT((result - targets).rowwise().norm().maxCoeff(), 0.001);
}

/// A rod of radius `radius` folded into a hairpin in the x-y plane: up from the origin along
/// `arm`, round a half turn of radius `fold`, then back down, closing on the first arm until the
/// two press `press` into each other at the ends. One surface: the ends touch in space but lie a
/// whole hairpin apart along it.
core::Mesh hairpin(double arm, double fold, double radius, double press) {
  core::Mesh mesh = testing::unit_sphere(64, 16);
  const double turn = M_PI * fold, length = 2 * arm + turn;
  const double closing = (2 * fold - (2 * radius - press)) / arm;  // x per metre down the second arm
  for (long v = 0; v < mesh.V.rows(); ++v) {
    const Eigen::Vector3d u = mesh.V.row(v).transpose();
    const double s = (u.y() + 1) / 2 * length;
    // Round ends, a constant section between them.
    const double section = radius * std::pow(std::max(0.0, 1 - std::pow(std::abs(u.y()), 6)), 1.0 / 6);
    const double across = std::hypot(u.x(), u.z());
    const Eigen::Vector2d offset =
        across > 0 ? Eigen::Vector2d(Eigen::Vector2d(u.x(), u.z()) / across * section) : Eigen::Vector2d::Zero();
    Eigen::Vector2d centre, tangent;
    if (s <= arm) {
      centre << 0, s;
      tangent << 0, 1;
    } else if (s <= arm + turn) {
      const double phi = (s - arm) / fold;
      centre << fold - fold * std::cos(phi), arm + fold * std::sin(phi);
      tangent << std::sin(phi), std::cos(phi);
    } else {
      const double down = s - arm - turn;
      centre << 2 * fold - closing * down, arm - down;
      tangent = Eigen::Vector2d(-closing, -1).normalized();
    }
    const Eigen::Vector2d normal(tangent.y(), -tangent.x());
    const Eigen::Vector2d p = centre + offset.x() * normal;
    mesh.V.row(v) << p.x(), p.y(), offset.y();
  }
  return mesh;
}

TEST(VolumeDeformer, OnlyDetoursOfABodysSizeAreCut) {
  // A hairpin of a body's height whose ends press together: a limb resting on the body, cut.
  EXPECT_GT(VolumeDeformer(hairpin(0.8, 0.08, 0.05, 0.04)).cut_elements(), 0);
  // The same hairpin a fifth of the size beside a body of 1.8 m: its ends are as close along the
  // surface as a fold of a garment or a blob fused to it, so the volume keeps it whole.
  const core::Mesh body = testing::ellipsoid(16, 24);
  EXPECT_EQ(VolumeDeformer(body).cut_elements(), 0);
  EXPECT_EQ(VolumeDeformer(side_by_side(hairpin(0.16, 0.016, 0.01, 0.008), body, 0.6)).cut_elements(), 0);
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
