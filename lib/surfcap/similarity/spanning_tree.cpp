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

template <class Matrix>
double symmetric_cost(const Matrix& costs, long i, long j) {
  return 0.5 * (static_cast<double>(costs(i, j)) + static_cast<double>(costs(j, i)));
}

/// The minimum spanning tree of the complete graph, edges ordered by (cost, a, b): a strict total
/// order, so the tree is unique (Kruskal's over all N²/2 edges would give the same one). Prim's
/// dense O(N²) form needs O(N) memory beyond the costs; the edges come back in ascending order.
template <class Matrix>
std::vector<Edge> minimum_spanning_edges(const Matrix& costs) {
  const int n = static_cast<int>(costs.rows());
  if (n == 0) return {};
  std::vector<Edge> best(static_cast<std::size_t>(n), Edge{std::numeric_limits<double>::infinity(), -1, -1});
  std::vector<char> in_tree(static_cast<std::size_t>(n), 0);
  std::vector<Edge> edges;
  edges.reserve(static_cast<std::size_t>(std::max(0, n - 1)));
  int current = 0;
  in_tree[0] = 1;
  for (int step = 1; step < n; ++step) {
    int next = -1;
    for (int v = 0; v < n; ++v) {
      if (in_tree[static_cast<std::size_t>(v)]) continue;
      const Edge edge{symmetric_cost(costs, current, v), std::min(current, v), std::max(current, v)};
      Edge& known = best[static_cast<std::size_t>(v)];
      if (known.a < 0 || edge < known) known = edge;
      if (next < 0 || known < best[static_cast<std::size_t>(next)]) next = v;
    }
    in_tree[static_cast<std::size_t>(next)] = 1;
    edges.push_back(best[static_cast<std::size_t>(next)]);
    current = next;
  }
  std::sort(edges.begin(), edges.end());
  return edges;
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

namespace {

template <class Matrix>
double threshold_of(const Matrix& costs) {
  double threshold = 0;
  for (long i = 0; i < costs.rows(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (long j = 0; j < costs.cols(); ++j)
      if (j != i) best = std::min(best, symmetric_cost(costs, i, j));
    if (std::isfinite(best)) threshold = std::max(threshold, best);
  }
  return threshold;
}

template <class Matrix>
SimilarityTree tree_of(const Matrix& costs, std::optional<int> root, std::optional<double> threshold,
                       const std::vector<bool>& eligible_roots);

}  // namespace

double automatic_threshold(const Eigen::MatrixXd& costs) { return threshold_of(costs); }
double automatic_threshold(const FloatRows& costs) { return threshold_of(costs); }

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
  return tree_of(costs, root, threshold, eligible_roots);
}

SimilarityTree similarity_tree(const FloatRows& costs, std::optional<int> root, std::optional<double> threshold,
                               const std::vector<bool>& eligible_roots) {
  return tree_of(costs, root, threshold, eligible_roots);
}

namespace {

template <class Matrix>
SimilarityTree tree_of(const Matrix& costs, std::optional<int> root, std::optional<double> threshold,
                       const std::vector<bool>& eligible_roots) {
  const int n = static_cast<int>(costs.rows());
  if (n == 0 || costs.cols() != n) throw core::internal_error("similarity_tree: the cost matrix must be square and non-empty");
  if (!eligible_roots.empty() &&
      (eligible_roots.size() != static_cast<std::size_t>(n) ||
       std::find(eligible_roots.begin(), eligible_roots.end(), true) == eligible_roots.end()))
    throw core::internal_error("similarity_tree: eligible roots must flag at least one of the N nodes");
  if (root && (*root < 0 || *root >= n)) throw core::bad_arguments("root node " + std::to_string(*root) + " is out of range");
  SimilarityTree tree;
  tree.threshold = threshold.value_or(threshold_of(costs));
  // Pruning the graph above the threshold, then joining what it disconnected by the cheapest
  // edges, is the minimum spanning tree: its edges up to the threshold span the pruned graph's
  // components, the ones above join them.
  const std::vector<Edge> accepted = minimum_spanning_edges(costs);
  const auto kept = static_cast<int>(
      std::count_if(accepted.begin(), accepted.end(), [&](const Edge& edge) { return edge.cost <= tree.threshold; }));
  tree.components_after_pruning = n - kept;
  if (tree.components_after_pruning > 1) tree.joining_edges = static_cast<int>(accepted.size()) - kept;
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

}  // namespace

double minimum_spanning_tree_cost(const Eigen::MatrixXd& costs) {
  double total = 0;
  for (const Edge& edge : minimum_spanning_edges(costs)) total += edge.cost;
  return total;
}

}  // namespace surfcap::similarity
