#include "surfcap/align/creases.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace surfcap::align {
namespace {

/// A closed can (radius r, height h, axis y): `segments` vertices per ring, `rings` rings on the
/// side from y = 0 to y = h, plus one centre vertex per cap. The two end rings are its rims.
struct Can {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  std::vector<int> rims;  ///< vertex indices of the two end rings, ascending
};

Can closed_can(double r, double h, int rings, int segments) {
  Can can;
  can.V.resize(rings * segments + 2, 3);
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const double a = 2 * std::numbers::pi * i / segments;
      can.V.row(j * segments + i) << r * std::cos(a), h * j / (rings - 1), r * std::sin(a);
    }
  const int bottom = rings * segments, top = bottom + 1;
  can.V.row(bottom) << 0, 0, 0;
  can.V.row(top) << 0, h, 0;
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j + 1 < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const int a = j * segments + i, b = j * segments + (i + 1) % segments;
      const int c = a + segments, d = b + segments;
      faces.emplace_back(a, c, b);  // outward: the ring runs counter-clockwise seen from −y
      faces.emplace_back(b, c, d);
    }
  for (int i = 0; i < segments; ++i) {
    faces.emplace_back(bottom, i, (i + 1) % segments);
    faces.emplace_back(top, (rings - 1) * segments + (i + 1) % segments, (rings - 1) * segments + i);
  }
  can.F.resize(static_cast<long>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) can.F.row(static_cast<long>(f)) = faces[f].transpose();
  for (int i = 0; i < segments; ++i) can.rims.push_back(i);
  for (int i = 0; i < segments; ++i) can.rims.push_back((rings - 1) * segments + i);
  return can;
}

TEST(Creases, TheConvexCreasesOfAClosedCanAreItsRimsAndInsideOutHasNone) {
  const Can can = closed_can(0.2, 0.5, 6, 24);
  // Outward orientation (the side's normal points away from the axis).
  const Eigen::Vector3d e1 = (can.V.row(can.F(0, 1)) - can.V.row(can.F(0, 0))).transpose();
  const Eigen::Vector3d e2 = (can.V.row(can.F(0, 2)) - can.V.row(can.F(0, 0))).transpose();
  const Eigen::Vector3d side_normal = e1.cross(e2);
  ASSERT_GT(side_normal.dot(can.V.row(can.F(0, 0)).transpose() - Eigen::Vector3d(0, can.V(can.F(0, 0), 1), 0)), 0);

  const Eigen::VectorXd angles = convex_crease_angles(can.V, can.F);
  for (const int v : can.rims) EXPECT_NEAR(angles(v), std::numbers::pi / 2, 1e-9) << v;
  EXPECT_EQ(convex_crease_vertices(can.V, can.F, std::numbers::pi / 4), can.rims);
  // Inside out, the rims are concave.
  Eigen::MatrixXi reversed = can.F;
  reversed.col(1) = can.F.col(2);
  reversed.col(2) = can.F.col(1);
  EXPECT_TRUE(convex_crease_vertices(can.V, reversed, std::numbers::pi / 4).empty());
  EXPECT_NEAR(convex_crease_angles(can.V, reversed).maxCoeff(), 0, 1e-12);
}

TEST(Creases, ClosestRimPointRespectsTheGateAndTheNormal) {
  const int segments = 24;
  const Can can = closed_can(0.2, 0.5, 6, segments);
  const CreaseLines lines(can.V, can.F, std::numbers::pi / 4, 0.1);
  EXPECT_EQ(lines.edge_count(), 2 * segments);
  // Outside the top rim, between two of its vertices: the closest rim point is on the chord.
  const double a = std::numbers::pi / segments;  // half-way between rim vertices 0 and 1
  const Eigen::Vector3d p(0.25 * std::cos(a), 0.53, 0.25 * std::sin(a));
  const Eigen::Vector3d bisector = Eigen::Vector3d(std::cos(a), 1, std::sin(a)).normalized();
  Eigen::Vector3d q;
  ASSERT_TRUE(lines.closest(p, bisector, 0.1, 0.5, q));
  const double chord = 0.2 * std::cos(a);  // distance of the chord's midpoint from the axis
  EXPECT_NEAR(q.y(), 0.5, 1e-12);
  EXPECT_NEAR(q.x(), chord * std::cos(a), 1e-9);
  EXPECT_NEAR(q.z(), chord * std::sin(a), 1e-9);
  // Facing the other way: no rim's bisector is within 60° of it.
  EXPECT_FALSE(lines.closest(p, -bisector, 0.1, 0.5, q));
  // Beyond the gate.
  EXPECT_FALSE(lines.closest(p, bisector, 0.03, 0.5, q));
  // Near the bottom rim, facing down and out: found there.
  ASSERT_TRUE(lines.closest(Eigen::Vector3d(0.22, -0.02, 0), Eigen::Vector3d(1, -1, 0).normalized(), 0.1, 0.5, q));
  EXPECT_NEAR(q.y(), 0, 1e-12);
  EXPECT_NEAR(q.x(), 0.2, 1e-9);
}

TEST(Creases, OnlyStraightStretchesOfCreasePassTheStraightnessTest) {
  // At a 0.08 m neighbourhood the rim of a wide can (r = 0.4 m, a hem) is nearly straight; the rim
  // of a thin one (r = 0.03 m, a finger) is a whole circle.
  const double radius = 0.08, max_ratio = 0.45;
  const Can wide = closed_can(0.4, 0.5, 6, 64);
  const Can thin = closed_can(0.03, 0.5, 6, 12);
  const std::vector<int> wide_rims = convex_crease_vertices(wide.V, wide.F, std::numbers::pi / 4);
  const std::vector<int> thin_rims = convex_crease_vertices(thin.V, thin.F, std::numbers::pi / 4);
  ASSERT_EQ(wide_rims, wide.rims);
  ASSERT_EQ(thin_rims, thin.rims);
  EXPECT_EQ(straight_crease_vertices(wide.V, wide_rims, radius, max_ratio), wide.rims);
  EXPECT_TRUE(straight_crease_vertices(thin.V, thin_rims, radius, max_ratio).empty());
  // ≥ 1 keeps everything; too few neighbours (a lone vertex) is not a stretch.
  EXPECT_EQ(straight_crease_vertices(thin.V, thin_rims, radius, 1), thin.rims);
  EXPECT_TRUE(straight_crease_vertices(wide.V, {wide.rims[0]}, radius, 0.99).empty());
  // The crease lines keep every rim edge (the reconstruction's creases are not filtered).
  EXPECT_EQ(CreaseLines(thin.V, thin.F, std::numbers::pi / 4, 0.1).edge_count(), 2 * 12);
}

}  // namespace
}  // namespace surfcap::align
