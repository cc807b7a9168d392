#include "surfcap/similarity/spanning_tree.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>

#include "surfcap/core/error.hpp"

namespace surfcap::similarity {
namespace {

class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(static_cast<std::size_t>(n)) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[static_cast<std::size_t>(x)] != x) {
      parent_[static_cast<std::size_t>(x)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(x)])];
      x = parent_[static_cast<std::size_t>(x)];
    }
    return x;
  }
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    return true;
  }

 private:
  std::vector<int> parent_;
};

struct Edge {
  double cost;
  int a, b;
  bool operator<(const Edge& other) const {
    return cost != other.cost ? cost < other.cost : (a != other.a ? a < other.a : b < other.b);
  }
};

struct Adjacent {
  int node;
  double cost;
};

/// Kruskal over `edges` (sorted in place); returns the accepted edges.
std::vector<Edge> kruskal(std::vector<Edge>& edges, DisjointSets& sets) {
  std::sort(edges.begin(), edges.end());
  std::vector<Edge> accepted;
  for (const Edge& edge : edges)
    if (sets.unite(edge.a, edge.b)) accepted.push_back(edge);
  return accepted;
}

/// Σ over nodes of the path cost from every possible root, by re-rooting in O(N).
std::vector<double> weighted_depths(const std::vector<std::vector<Adjacent>>& adjacency) {
  const int n = static_cast<int>(adjacency.size());
  std::vector<int> order, parent(static_cast<std::size_t>(n), -1);
  std::vector<double> parent_cost(static_cast<std::size_t>(n), 0.0), distance(static_cast<std::size_t>(n), 0.0);
  order.reserve(static_cast<std::size_t>(n));
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  order.push_back(0);
  seen[0] = 1;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (const auto& next : adjacency[static_cast<std::size_t>(order[i])])
      if (!seen[static_cast<std::size_t>(next.node)]) {
        seen[static_cast<std::size_t>(next.node)] = 1;
        parent[static_cast<std::size_t>(next.node)] = order[i];
        parent_cost[static_cast<std::size_t>(next.node)] = next.cost;
        distance[static_cast<std::size_t>(next.node)] = distance[static_cast<std::size_t>(order[i])] + next.cost;
        order.push_back(next.node);
      }
  std::vector<long> size(static_cast<std::size_t>(n), 1);
  for (auto it = order.rbegin(); it != order.rend(); ++it)
    if (parent[static_cast<std::size_t>(*it)] >= 0) size[static_cast<std::size_t>(parent[static_cast<std::size_t>(*it)])] += size[static_cast<std::size_t>(*it)];
  std::vector<double> total(static_cast<std::size_t>(n));
  total[0] = std::accumulate(distance.begin(), distance.end(), 0.0);
  // Moving the root across an edge brings size(child) nodes closer and the rest farther.
  for (std::size_t i = 1; i < order.size(); ++i) {
    const auto v = static_cast<std::size_t>(order[i]);
    total[v] = total[static_cast<std::size_t>(parent[v])] + parent_cost[v] * static_cast<double>(n - 2 * size[v]);
  }
  return total;
}

}  // namespace

double automatic_threshold(const Eigen::MatrixXd& costs) {
  double threshold = 0;
  for (long i = 0; i < costs.rows(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (long j = 0; j < costs.cols(); ++j)
      if (j != i) best = std::min(best, 0.5 * (costs(i, j) + costs(j, i)));
    if (std::isfinite(best)) threshold = std::max(threshold, best);
  }
  return threshold;
}

std::vector<bool> wide_stance_roots(const std::vector<double>& stance, double fraction) {
  if (stance.empty()) return {};
  std::vector<double> sorted = stance;
  std::sort(sorted.begin(), sorted.end(), std::greater<>());
  const auto keep = static_cast<std::size_t>(
      std::clamp(std::ceil(fraction * static_cast<double>(sorted.size())), 1.0, static_cast<double>(sorted.size())));
  const double limit = sorted[keep - 1];
  std::vector<bool> eligible(stance.size());
  for (std::size_t i = 0; i < stance.size(); ++i) eligible[i] = stance[i] >= limit;
  return eligible;
}

SimilarityTree similarity_tree(const Eigen::MatrixXd& costs, std::optional<int> root, std::optional<double> threshold,
                               const std::vector<bool>& eligible_roots) {
  const int n = static_cast<int>(costs.rows());
  if (n == 0 || costs.cols() != n) throw core::internal_error("similarity_tree: the cost matrix must be square and non-empty");
  if (!eligible_roots.empty() &&
      (eligible_roots.size() != static_cast<std::size_t>(n) ||
       std::find(eligible_roots.begin(), eligible_roots.end(), true) == eligible_roots.end()))
    throw core::internal_error("similarity_tree: eligible roots must flag at least one of the N nodes");
  if (root && (*root < 0 || *root >= n)) throw core::bad_arguments("root node " + std::to_string(*root) + " is out of range");
  SimilarityTree tree;
  tree.threshold = threshold.value_or(automatic_threshold(costs));
  std::vector<Edge> kept, rest;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const double cost = 0.5 * (costs(i, j) + costs(j, i));
      (cost <= tree.threshold ? kept : rest).push_back({cost, i, j});
    }
  DisjointSets sets(n);
  std::vector<Edge> accepted = kruskal(kept, sets);
  tree.components_after_pruning = n - static_cast<int>(accepted.size());
  if (tree.components_after_pruning > 1) {
    // Pruning disconnected the graph: join the components by their cheapest edges.
    std::vector<Edge> joining = kruskal(rest, sets);
    tree.joining_edges = static_cast<int>(joining.size());
    accepted.insert(accepted.end(), joining.begin(), joining.end());
  }
  std::vector<std::vector<Adjacent>> adjacency(static_cast<std::size_t>(n));
  for (const Edge& edge : accepted) {
    adjacency[static_cast<std::size_t>(edge.a)].push_back({edge.b, edge.cost});
    adjacency[static_cast<std::size_t>(edge.b)].push_back({edge.a, edge.cost});
    tree.total_cost += edge.cost;
  }
  for (auto& neighbours : adjacency)
    std::sort(neighbours.begin(), neighbours.end(), [](const Adjacent& x, const Adjacent& y) { return x.node < y.node; });
  const std::vector<double> depths = weighted_depths(adjacency);
  if (root) {
    tree.root = *root;
  } else {
    tree.root = -1;
    for (int i = 0; i < n; ++i)
      if ((eligible_roots.empty() || eligible_roots[static_cast<std::size_t>(i)]) &&
          (tree.root < 0 || depths[static_cast<std::size_t>(i)] < depths[static_cast<std::size_t>(tree.root)]))
        tree.root = i;
  }
  tree.weighted_depth = depths[static_cast<std::size_t>(tree.root)];
  // Breadth-first from the root: the order in which frames can be aligned.
  tree.depth.assign(static_cast<std::size_t>(n), -1);
  std::queue<int> queue;
  queue.push(tree.root);
  tree.depth[static_cast<std::size_t>(tree.root)] = 0;
  while (!queue.empty()) {
    const int node = queue.front();
    queue.pop();
    for (const auto& next : adjacency[static_cast<std::size_t>(node)]) {
      if (tree.depth[static_cast<std::size_t>(next.node)] >= 0) continue;
      tree.depth[static_cast<std::size_t>(next.node)] = tree.depth[static_cast<std::size_t>(node)] + 1;
      tree.edges.push_back({node, next.node, next.cost});
      queue.push(next.node);
    }
  }
  return tree;
}

double minimum_spanning_tree_cost(const Eigen::MatrixXd& costs) {
  const int n = static_cast<int>(costs.rows());
  std::vector<Edge> edges;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) edges.push_back({0.5 * (costs(i, j) + costs(j, i)), i, j});
  DisjointSets sets(n);
  double total = 0;
  for (const Edge& edge : kruskal(edges, sets)) total += edge.cost;
  return total;
}

}  // namespace surfcap::similarity
