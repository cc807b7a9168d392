#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/similarity/shape_histogram.hpp"
#include "surfcap/similarity/volume_sampling.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using similarity::ShapeHistogramOptions;

/// A person-sized, asymmetric, star-shaped closed surface meshed as a UV sphere with the given
/// resolution (different resolutions = independent remeshings of one shape). `pose` changes
/// the bumps the way a different pose would.
core::Mesh body(int rings, int segments, double pose = 0.0) {
  core::Mesh mesh = testing::make_sphere(rings, segments, 1.0);
  for (long v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector3d d = mesh.V.row(v).normalized();
    const double theta = std::acos(std::clamp(d.y(), -1.0, 1.0)), phi = std::atan2(d.z(), d.x());
    const double r = 1.0 + 0.25 * std::sin(3 * phi + 0.4) * std::sin(theta) + 0.15 * std::cos(2 * theta) +
                     pose * std::cos(phi) * std::sin(2 * theta);
    mesh.V.row(v) = (r * d).cwiseProduct(Eigen::Vector3d(0.3, 0.85, 0.2)).transpose();
  }
  return mesh;
}

core::Mesh transformed(core::Mesh mesh, double angle, const Eigen::Vector3d& shift) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
  mesh.V = (mesh.V * R.transpose()).rowwise() + shift.transpose();
  return mesh;
}

double relative_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const ShapeHistogramOptions& options) {
  return similarity::match_histograms(a, b, options).distance / a.norm();
}

TEST(VolumeSampling, MeasuresTheEnclosedVolume) {
  const core::Mesh sphere = testing::make_sphere(48, 96, 0.5);
  const double spacing = 0.01;
  const double volume = similarity::interior_samples(sphere, spacing).col(3).sum() * std::pow(spacing, 3);
  EXPECT_NEAR(volume, 4.0 / 3.0 * M_PI * 0.125, 0.01 * 4.0 / 3.0 * M_PI * 0.125);
  // Reversed orientation (inside-out) encloses nothing under the winding rule.
  core::Mesh inverted = sphere;
  inverted.F.col(1).swap(inverted.F.col(2));
  EXPECT_EQ(similarity::interior_samples(inverted, spacing).rows(), 0);
}

TEST(ShapeHistogram, MassSumsToOneAndLayoutMatches) {
  const ShapeHistogramOptions options;
  const Eigen::VectorXd h = similarity::shape_histogram(body(24, 48), options);
  ASSERT_EQ(h.size(), options.size());
  double mass = 0;
  for (long c = 0; c < h.size(); c += 2 * options.azimuth_order + 1) mass += h(c);
  EXPECT_NEAR(mass, 1.0, 1e-9);
}

TEST(ShapeHistogram, RotationTranslationAndRemeshingStayWithinOnePercent) {
  const ShapeHistogramOptions options;
  const Eigen::VectorXd original = similarity::shape_histogram(body(32, 64), options);
  for (const double angle : {0.3, 1.0, 2.5, -2.0}) {
    const auto moved = transformed(body(32, 64), angle, {0.37, 0.05, -1.21});
    EXPECT_LT(relative_distance(original, similarity::shape_histogram(moved, options), options), 0.01)
        << "rotation " << angle;
  }
  const Eigen::VectorXd remeshed = similarity::shape_histogram(body(41, 77), options);
  EXPECT_LT(relative_distance(original, remeshed, options), 0.01);
  const Eigen::VectorXd both = similarity::shape_histogram(transformed(body(27, 55), 0.8, {1, 0, 2}), options);
  EXPECT_LT(relative_distance(original, both, options), 0.01);
}

TEST(ShapeHistogram, DifferentPosesAreFarApart) {
  const ShapeHistogramOptions options;
  const Eigen::VectorXd a = similarity::shape_histogram(body(32, 64), options);
  const Eigen::VectorXd b = similarity::shape_histogram(body(32, 64, 0.3), options);
  const Eigen::VectorXd c = similarity::shape_histogram(body(32, 64, 0.6), options);
  EXPECT_GT(relative_distance(a, b, options), 0.05);
  EXPECT_GT(relative_distance(a, c, options), relative_distance(a, b, options));  // monotone in the change
}

TEST(ShapeHistogram, FftAndExhaustiveSearchAgree) {
  const ShapeHistogramOptions options;
  const Eigen::VectorXd a = similarity::shape_histogram(body(24, 48), options);
  const Eigen::VectorXd b = similarity::shape_histogram(transformed(body(24, 48, 0.2), 1.3, {0, 0, 0}), options);
  const auto fft = similarity::match_histograms(a, b, options, similarity::RotationSearch::fft);
  const auto exhaustive = similarity::match_histograms(a, b, options, similarity::RotationSearch::exhaustive);
  EXPECT_NEAR(fft.distance, exhaustive.distance, 1e-6);
  EXPECT_NEAR(std::abs(fft.angle), 1.3, 0.1);  // recovers the rotation
}

TEST(ShapeHistogram, OpenSurfaceIsSampledWithItsHolesClosed) {
  // An ellipsoid cut flat below (the south pole and the last 8 rings removed: open "soles").
  const int rings = 40, segments = 64;
  core::Mesh closed = testing::make_sphere(rings, segments, 1.0);
  closed.V = closed.V * Eigen::Vector3d(0.3, 0.85, 0.2).asDiagonal();
  const int first_cut = 1 + (rings - 9) * segments;  // ring 32 and below lose their faces
  const core::Mesh open =
      testing::with_faces(closed, [&](long f) { return closed.F.row(f).maxCoeff() < first_cut + segments; });
  ASSERT_EQ(core::check_mesh(open).boundary_edges, segments);
  // The same cut closed by the reconstruction repair (CGAL's minimum-weight triangulation of the
  // flat loop) encloses the same region: the histograms agree.
  core::Mesh repaired = open;
  core::RepairLimits generous;
  generous.max_hole_edges = 100;
  generous.max_hole_perimeter = 2.0;
  core::repair_mesh(repaired, generous, "cut.ply");
  ASSERT_TRUE(core::check_mesh(repaired).closed());
  const ShapeHistogramOptions options;
  const Eigen::VectorXd a = similarity::shape_histogram(open, options), b = similarity::shape_histogram(repaired, options);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-6);
  // Sampled as it is, the open surface would lose the columns above its sole (the winding rule never
  // enters through the missing sole).
  double as_is = 0, with_holes_closed = 0;
  similarity::VolumeSampler(open, 0.01).visit([&](double, double, double, double w) { as_is += w; });
  similarity::VolumeSampler(repaired, 0.01).visit([&](double, double, double, double w) { with_holes_closed += w; });
  EXPECT_LT(as_is, 0.7 * with_holes_closed);
}

TEST(ShapeHistogram, TinySurfaceIsBadInput) {
  core::Mesh tiny = testing::make_sphere(6, 8, 0.001);
  EXPECT_THROW(similarity::shape_histogram(tiny, {}), core::Error);
}

}  // namespace
}  // namespace surfcap
