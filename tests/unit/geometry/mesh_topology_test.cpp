#include "surfcap/geometry/mesh_topology.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

TEST(MeshTopology, AdjacencyOneRingAndRings) {
  const core::Mesh sphere = testing::make_sphere(8, 12, 1.0);
  const auto adjacency = vertex_adjacency(sphere.F, sphere.vertex_count());
  long degree_sum = 0;
  for (std::size_t v = 0; v < adjacency.size(); ++v) {
    degree_sum += static_cast<long>(adjacency[v].size());
    for (int w : adjacency[v]) EXPECT_TRUE(std::binary_search(adjacency[w].begin(), adjacency[w].end(), static_cast<int>(v)));
  }
  // Closed genus-0 triangle mesh: E = 3F/2 and V − E + F = 2.
  EXPECT_EQ(degree_sum, 3 * sphere.face_count());
  EXPECT_EQ(sphere.vertex_count() - degree_sum / 2 + sphere.face_count(), 2);
  EXPECT_EQ(one_ring(adjacency, 5), adjacency[5]);
  const auto rings = ring_distance(adjacency, {0});
  const auto grown = grow_region(adjacency, {0}, 2);
  for (int v : grown) EXPECT_LE(rings[v], 2);
  EXPECT_EQ(grown.size(), static_cast<std::size_t>(std::count_if(rings.begin(), rings.end(), [](int r) { return r >= 0 && r <= 2; })));
  EXPECT_EQ(grow_region(adjacency, {0}, 1).size(), adjacency[0].size() + 1);
}

TEST(MeshTopology, SubmeshKeepsInteriorFacesAndMaps) {
  const core::Mesh sphere = testing::make_sphere(8, 12, 1.0);
  std::vector<int> upper;
  for (Eigen::Index v = 0; v < sphere.V.rows(); ++v)
    if (sphere.V(v, 1) > 0.1) upper.push_back(static_cast<int>(v));
  const Submesh sub = extract_submesh(sphere.F, sphere.vertex_count(), upper);
  ASSERT_EQ(sub.vertices.size(), upper.size());
  for (std::size_t i = 0; i < sub.vertices.size(); ++i) EXPECT_EQ(sub.global_to_local[sub.vertices[i]], static_cast<int>(i));
  for (Eigen::Index f = 0; f < sub.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(sub.vertices[sub.F(f, k)], sphere.F(sub.faces[f], k));
  long expected = 0;
  for (Eigen::Index f = 0; f < sphere.F.rows(); ++f)
    expected += sphere.V(sphere.F(f, 0), 1) > 0.1 && sphere.V(sphere.F(f, 1), 1) > 0.1 && sphere.V(sphere.F(f, 2), 1) > 0.1;
  EXPECT_EQ(sub.F.rows(), expected);
}

TEST(MeshTopology, EdgeGeodesicDistanceOnSphereBoundsArc) {
  const core::Mesh sphere = testing::make_sphere(16, 24, 1.0);
  const auto adjacency = vertex_adjacency(sphere.F, sphere.vertex_count());
  Eigen::Index top;
  sphere.V.col(1).maxCoeff(&top);
  const auto d = edge_geodesic_distance(sphere.V, adjacency, {static_cast<int>(top)});
  for (Eigen::Index v = 0; v < sphere.V.rows(); ++v) {
    const double arc = std::acos(std::clamp(sphere.V.row(v).dot(sphere.V.row(top)), -1.0, 1.0));
    EXPECT_GE(d[v], (sphere.V.row(v) - sphere.V.row(top)).norm() - 1e-9);  // never shorter than the chord
    EXPECT_LE(d[v], 1.3 * arc + 1e-9);  // and not much longer on a regular sphere
  }
}

}  // namespace
}  // namespace surfcap::geometry
