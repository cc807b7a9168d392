#include "surfcap/align/surface_patches.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>

#include "surfcap/core/error.hpp"
#include "surfcap/geometry/mesh_topology.hpp"

namespace surfcap::align {

namespace {

using Adjacency = std::vector<std::vector<int>>;

/// Lowers `distance` (and sets `label`) around a new seed; only vertices that get closer are visited.
void grow_seed(const Eigen::MatrixXd& V, const Adjacency& adjacency, int seed, int seed_label,
               std::vector<double>& distance, std::vector<int>& label) {
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  distance[static_cast<std::size_t>(seed)] = 0;
  label[static_cast<std::size_t>(seed)] = seed_label;
  queue.emplace(0.0, seed);
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[static_cast<std::size_t>(v)]) continue;
    for (const int w : adjacency[static_cast<std::size_t>(v)]) {
      const double candidate = d + (V.row(v) - V.row(w)).norm();
      auto& current = distance[static_cast<std::size_t>(w)];
      if (candidate < current || (candidate == current && seed_label < label[static_cast<std::size_t>(w)])) {
        current = candidate;
        label[static_cast<std::size_t>(w)] = seed_label;
        queue.emplace(candidate, w);
      }
    }
  }
}

int farthest_vertex(const std::vector<double>& distance) {
  int best = 0;
  for (int v = 1; v < static_cast<int>(distance.size()); ++v)
    if (distance[static_cast<std::size_t>(v)] > distance[static_cast<std::size_t>(best)]) best = v;
  return best;
}

}  // namespace

PatchSet surface_patches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int count) {
  if (count < 1) throw core::internal_error("surface_patches: count must be ≥ 1");
  const long n = V.rows();
  const Adjacency adjacency = geometry::vertex_adjacency(F, n);
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> distance(static_cast<std::size_t>(n), infinity);
  std::vector<int> label(static_cast<std::size_t>(n), -1);
  // The first seed: the vertex farthest from vertex 0 (an extremity, independent of vertex order
  // in practice).
  {
    std::vector<double> from_zero(static_cast<std::size_t>(n), infinity);
    std::vector<int> scratch(static_cast<std::size_t>(n), -1);
    grow_seed(V, adjacency, 0, 0, from_zero, scratch);
    for (auto& d : from_zero)
      if (d == infinity) d = -1;
    grow_seed(V, adjacency, farthest_vertex(from_zero), 0, distance, label);
  }
  int seeds = 1;
  while (seeds < std::min<long>(count, n)) {
    grow_seed(V, adjacency, farthest_vertex(distance), seeds, distance, label);
    ++seeds;
  }
  // Components the seeds did not reach get their own patches.
  for (long v = 0; v < n; ++v)
    if (label[static_cast<std::size_t>(v)] < 0) grow_seed(V, adjacency, static_cast<int>(v), seeds++, distance, label);
  PatchSet set;
  set.label = std::move(label);
  set.vertices.resize(static_cast<std::size_t>(seeds));
  for (long v = 0; v < n; ++v) set.vertices[static_cast<std::size_t>(set.label[static_cast<std::size_t>(v)])].push_back(static_cast<int>(v));
  return set;
}

std::vector<PatchSet> patch_hierarchy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int initial, int levels) {
  std::vector<PatchSet> hierarchy;
  long count = initial;
  for (int level = 0; level < levels; ++level, count *= 2)
    hierarchy.push_back(surface_patches(V, F, static_cast<int>(std::clamp<long>(count, 1, std::max<long>(1, V.rows() / 4)))));
  return hierarchy;
}

}  // namespace surfcap::align
