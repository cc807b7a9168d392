#include "surfcap/geometry/mesh_topology.hpp"

#include <algorithm>
#include <deque>
#include <functional>
#include <limits>
#include <queue>

#include "surfcap/core/error.hpp"

namespace surfcap::geometry {

std::vector<std::vector<int>> vertex_adjacency(const Eigen::MatrixXi& F, long vertex_count) {
  std::vector<std::vector<int>> adjacency(static_cast<std::size_t>(vertex_count));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (a < 0 || b < 0 || a >= vertex_count || b >= vertex_count)
        throw core::internal_error("vertex_adjacency: face index out of range");
      adjacency[a].push_back(b);
      adjacency[b].push_back(a);
    }
  for (auto& neighbours : adjacency) {
    std::sort(neighbours.begin(), neighbours.end());
    neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
  }
  return adjacency;
}

std::vector<int> one_ring(const std::vector<std::vector<int>>& adjacency, int vertex) {
  return adjacency.at(static_cast<std::size_t>(vertex));
}

Submesh extract_submesh(const Eigen::MatrixXi& F, long vertex_count, const std::vector<int>& vertices) {
  Submesh sub;
  sub.vertices = vertices;
  std::sort(sub.vertices.begin(), sub.vertices.end());
  sub.vertices.erase(std::unique(sub.vertices.begin(), sub.vertices.end()), sub.vertices.end());
  sub.global_to_local.assign(static_cast<std::size_t>(vertex_count), -1);
  for (std::size_t i = 0; i < sub.vertices.size(); ++i) {
    const int v = sub.vertices[i];
    if (v < 0 || v >= vertex_count) throw core::internal_error("extract_submesh: vertex index out of range");
    sub.global_to_local[v] = static_cast<int>(i);
  }
  std::vector<Eigen::Vector3i> faces;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = sub.global_to_local[F(f, 0)], b = sub.global_to_local[F(f, 1)],
              c = sub.global_to_local[F(f, 2)];
    if (a < 0 || b < 0 || c < 0) continue;
    faces.emplace_back(a, b, c);
    sub.faces.push_back(static_cast<int>(f));
  }
  sub.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) sub.F.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  return sub;
}

std::vector<int> ring_distance(const std::vector<std::vector<int>>& adjacency, const std::vector<int>& seeds) {
  std::vector<int> distance(adjacency.size(), -1);
  std::deque<int> queue;
  for (int s : seeds)
    if (distance.at(static_cast<std::size_t>(s)) < 0) {
      distance[s] = 0;
      queue.push_back(s);
    }
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    for (int w : adjacency[v])
      if (distance[w] < 0) {
        distance[w] = distance[v] + 1;
        queue.push_back(w);
      }
  }
  return distance;
}

std::vector<int> grow_region(const std::vector<std::vector<int>>& adjacency, const std::vector<int>& seeds,
                             int rings) {
  const std::vector<int> distance = ring_distance(adjacency, seeds);
  std::vector<int> region;
  for (std::size_t v = 0; v < distance.size(); ++v)
    if (distance[v] >= 0 && distance[v] <= rings) region.push_back(static_cast<int>(v));
  return region;
}

std::vector<double> edge_geodesic_distance(const Eigen::MatrixXd& V,
                                           const std::vector<std::vector<int>>& adjacency,
                                           const std::vector<int>& seeds) {
  std::vector<double> distance(adjacency.size(), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (int s : seeds) {
    distance.at(static_cast<std::size_t>(s)) = 0;
    queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    for (int w : adjacency[v]) {
      const double candidate = d + (V.row(v) - V.row(w)).norm();
      if (candidate < distance[w]) {
        distance[w] = candidate;
        queue.emplace(candidate, w);
      }
    }
  }
  return distance;
}

}  // namespace surfcap::geometry
