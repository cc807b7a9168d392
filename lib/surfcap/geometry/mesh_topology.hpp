#pragma once
// Vertex neighbourhoods of a triangle mesh: adjacency, one-rings, submeshes with index maps,
// region growing by rings and graph (edge-length) geodesic distances.
#include <Eigen/Core>
#include <vector>

namespace surfcap::geometry {

/// Sorted neighbour lists: adjacency[i] = vertices sharing an edge with i (n = vertex_count).
std::vector<std::vector<int>> vertex_adjacency(const Eigen::MatrixXi& F, long vertex_count);

/// The vertices sharing an edge with `vertex` (sorted).
std::vector<int> one_ring(const std::vector<std::vector<int>>& adjacency, int vertex);

/// A submesh: the faces whose three vertices are all in the set, re-indexed.
struct Submesh {
  std::vector<int> vertices;           ///< local → global vertex index (sorted ascending)
  std::vector<int> global_to_local;    ///< global → local, −1 when not in the submesh
  Eigen::MatrixXi F;                   ///< faces in local indices
  std::vector<int> faces;              ///< local face → global face index
};
Submesh extract_submesh(const Eigen::MatrixXi& F, long vertex_count, const std::vector<int>& vertices);

/// `seeds` grown by `rings` rings of neighbours (sorted, unique).
std::vector<int> grow_region(const std::vector<std::vector<int>>& adjacency, const std::vector<int>& seeds,
                             int rings);

/// Number of edges from the nearest seed (breadth first); −1 where unreachable.
std::vector<int> ring_distance(const std::vector<std::vector<int>>& adjacency, const std::vector<int>& seeds);

/// Shortest path length along mesh edges from the nearest seed (Dijkstra, metres); +inf where
/// unreachable.
std::vector<double> edge_geodesic_distance(const Eigen::MatrixXd& V,
                                           const std::vector<std::vector<int>>& adjacency,
                                           const std::vector<int>& seeds);

}  // namespace surfcap::geometry
