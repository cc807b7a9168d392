#include "surfcap/align/tree_partition.hpp"

#include <algorithm>
#include <numeric>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::align {

TreePartition partition_tree(const AlignmentTree& tree) {
  const std::size_t count = tree.nodes.size();
  std::vector<long> subtree(count, 1), parent(count, -1);
  for (auto edge = tree.edges.rbegin(); edge != tree.edges.rend(); ++edge) {  // children before parents
    subtree[static_cast<std::size_t>(edge->parent)] += subtree[static_cast<std::size_t>(edge->child)];
    parent[static_cast<std::size_t>(edge->child)] = edge->parent;
  }
  // cost(B) = 1 + #{non-root nodes with subtree > B} + B over the non-root subtree sizes B: the
  // largest unit is then B itself (the largest subtree of at most B nodes hangs from the trunk).
  std::vector<long> sizes;
  for (std::size_t node = 0; node < count; ++node)
    if (static_cast<long>(node) != tree.root) sizes.push_back(subtree[node]);
  std::sort(sizes.begin(), sizes.end());
  TreePartition partition;
  long best_cost = -1;
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    if (k + 1 < sizes.size() && sizes[k + 1] == sizes[k]) continue;  // the last of equal sizes
    const long above = static_cast<long>(sizes.size() - k - 1);
    const long cost = 1 + above + sizes[k];
    if (best_cost < 0 || cost <= best_cost) {
      best_cost = cost;
      partition.bound = sizes[k];
    }
  }
  partition.unit_of.assign(count, -1);
  for (std::size_t node = 0; node < count; ++node) {
    const long p = parent[node];
    const bool unit_root = static_cast<long>(node) != tree.root && subtree[node] <= partition.bound &&
                           (p == tree.root || subtree[static_cast<std::size_t>(p)] > partition.bound);
    if (unit_root) {
      partition.unit_roots.push_back(static_cast<long>(node));
      partition.unit_sizes.push_back(subtree[node]);
    }
  }
  for (std::size_t unit = 0; unit < partition.unit_roots.size(); ++unit)
    partition.unit_of[static_cast<std::size_t>(partition.unit_roots[unit])] = static_cast<long>(unit);
  for (const auto& edge : tree.edges) {  // parents before children: a unit spreads down its subtree
    auto& child = partition.unit_of[static_cast<std::size_t>(edge.child)];
    if (child < 0) child = partition.unit_of[static_cast<std::size_t>(edge.parent)];
  }
  partition.trunk_size = std::count(partition.unit_of.begin(), partition.unit_of.end(), -1L);
  return partition;
}

std::vector<std::vector<long>> group_units(const TreePartition& partition, int jobs) {
  if (jobs < 1) throw core::internal_error("group_units: jobs < 1");
  std::vector<long> order(static_cast<std::size_t>(partition.units()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](long a, long b) {
    return partition.unit_sizes[static_cast<std::size_t>(a)] > partition.unit_sizes[static_cast<std::size_t>(b)];
  });
  std::vector<std::vector<long>> groups(static_cast<std::size_t>(jobs));
  std::vector<long> load(static_cast<std::size_t>(jobs), 0);
  for (const long unit : order) {
    const auto lightest = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    groups[lightest].push_back(unit);
    load[lightest] += partition.unit_sizes[static_cast<std::size_t>(unit)];
  }
  for (auto& group : groups) std::sort(group.begin(), group.end());
  return groups;
}

}  // namespace surfcap::align
