#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "surfcap/core/surface_topology.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using testing::signed_volume;

/// A torus (genus 1) of `rings` × `segments` quads split into triangles, outward oriented.
core::Mesh make_torus(int rings, int segments, double major, double minor) {
  core::Mesh mesh;
  mesh.V.resize(rings * segments, 3);
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double u = 2 * M_PI * i / rings, v = 2 * M_PI * j / segments;
      mesh.V.row(i * segments + j) << (major + minor * std::cos(v)) * std::cos(u), minor * std::sin(v),
          (major + minor * std::cos(v)) * std::sin(u);
    }
  mesh.F.resize(2 * rings * segments, 3);
  auto at = [&](int i, int j) { return (i % rings) * segments + (j % segments); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      mesh.F.row(2 * (i * segments + j)) << at(i, j), at(i, j + 1), at(i + 1, j);
      mesh.F.row(2 * (i * segments + j) + 1) << at(i, j + 1), at(i + 1, j + 1), at(i + 1, j);
    }
  return mesh;
}

/// `mesh` without the faces touching vertices 0..last (a UV sphere's north cap).
core::Mesh without_cap(const core::Mesh& mesh, int last) {
  return testing::with_faces(mesh, [&](long f) { return mesh.F.row(f).minCoeff() > last; });
}

core::Mesh side_by_side(const core::Mesh& a, const core::Mesh& b, double shift) {
  core::Mesh both;
  both.V.resize(a.V.rows() + b.V.rows(), 3);
  both.V << a.V, b.V.rowwise() + Eigen::RowVector3d(shift, 0, 0);
  both.F.resize(a.F.rows() + b.F.rows(), 3);
  both.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return both;
}

TEST(SurfaceTopology, SphereTorusAndTwoPieces) {
  const core::Mesh sphere = testing::make_sphere(12, 16);
  const core::SurfaceTopology s = core::surface_topology(sphere);
  EXPECT_EQ(s.holes, 0);
  EXPECT_EQ(s.components, 1);
  EXPECT_EQ(s.genus, 0);
  const core::Mesh torus = make_torus(24, 12, 1.0, 0.3);
  EXPECT_EQ(core::surface_topology(torus).genus, 1);
  EXPECT_EQ(core::surface_topology(torus).components, 1);
  const core::SurfaceTopology merged = core::surface_topology(side_by_side(torus, side_by_side(torus, sphere, 3.0), 3.0));
  EXPECT_EQ(merged.components, 3);
  EXPECT_EQ(merged.genus, 2);
  EXPECT_EQ(merged.holes, 0);
}

TEST(SurfaceTopology, HolesAreLoopsWithTheirPerimeter) {
  const int segments = 32;
  const core::Mesh sphere = testing::make_sphere(16, segments);
  // North pole and rings 1..3 removed: ring 4 (radius sin(π/4)) bounds one hole.
  const core::Mesh open = without_cap(sphere, 3 * segments);
  const auto loops = core::boundary_loops(open);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].vertices.size(), static_cast<std::size_t>(segments));
  const double chord = 2 * std::sin(M_PI / 4) * std::sin(M_PI / segments);
  EXPECT_NEAR(loops[0].perimeter, segments * chord, 1e-12);
  const core::SurfaceTopology t = core::surface_topology(open);
  EXPECT_EQ(t.holes, 1);
  EXPECT_EQ(t.largest_hole_edges, segments);
  EXPECT_EQ(t.genus, 0);
  // A torus cut open across its tube keeps genus 0 with two holes (a bent cylinder).
  const core::Mesh tube = make_torus(24, 12, 1.0, 0.3);
  const core::Mesh cut = testing::with_faces(tube, [](long f) { return f / 24 != 0; });  // ring 0's faces go
  const core::SurfaceTopology c = core::surface_topology(cut);
  EXPECT_EQ(c.holes, 2);
  EXPECT_EQ(c.genus, 0);
  EXPECT_EQ(c.components, 1);
}

TEST(SurfaceTopology, ClosingAPlanarCutGivesTheFlatCap) {
  const int segments = 40;
  const core::Mesh sphere = testing::make_sphere(20, segments);
  const core::Mesh open = without_cap(sphere, 5 * segments);  // cut at the plane of ring 6
  const core::Mesh closed = core::close_holes(open);
  EXPECT_EQ(core::boundary_loops(closed).size(), 0u);
  EXPECT_EQ(closed.vertex_count(), open.vertex_count() + 1);
  EXPECT_EQ(closed.face_count(), open.face_count() + segments);
  // The volume of the closed polyhedron is the sphere's minus the cut-off cap: exactly the
  // volume of the sphere mesh with its cap replaced by a flat polygon at ring 6's height.
  const double y = std::cos(M_PI * 6 / 20);
  // The removed cap, closed the same way, is the complement of `closed` in the sphere polyhedron.
  const core::Mesh top = testing::with_faces(sphere, [&](long f) { return sphere.F.row(f).minCoeff() <= 5 * segments; });
  const double cap = signed_volume(core::close_holes(top));
  EXPECT_GT(cap, 0);
  EXPECT_NEAR(signed_volume(closed) + cap, signed_volume(sphere), 1e-12);
  // And every new face lies in the cut plane.
  for (long f = open.face_count(); f < closed.face_count(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(closed.V(closed.F(f, k), 1), y, 1e-12);
}

}  // namespace
}  // namespace surfcap
