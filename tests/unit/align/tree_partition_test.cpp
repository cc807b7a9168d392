#include "surfcap/align/tree_partition.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "surfcap/align/tree_alignment.hpp"

namespace surfcap::align {
namespace {

/// A tree from parent links (parents[n] < n except the root 0's −1), its edges breadth first.
AlignmentTree tree_of(const std::vector<long>& parents) {
  AlignmentTree tree;
  const std::size_t count = parents.size();
  tree.nodes.resize(count);
  std::vector<int> depth(count, 0);
  std::vector<long> frontier = {0};
  while (!frontier.empty()) {
    std::vector<long> next;
    for (const long parent : frontier)
      for (std::size_t child = 0; child < count; ++child)
        if (parents[child] == parent) {
          depth[child] = depth[static_cast<std::size_t>(parent)] + 1;
          tree.edges.push_back({parent, static_cast<long>(child), 0.0, depth[child]});
          next.push_back(static_cast<long>(child));
        }
    frontier = next;
  }
  return tree;
}

/// Chains of sequences joined at a few frames, as similarity trees of captured motions look:
/// long runs of consecutive frames with branches where two motions meet.
std::vector<long> capture_like_parents(std::size_t count, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<long> parents(count, -1);
  for (std::size_t node = 1; node < count; ++node)
    parents[node] = random() % 5 == 0 ? static_cast<long>(random() % node) : static_cast<long>(node - 1);
  return parents;
}

std::vector<long> subtree_sizes(const AlignmentTree& tree) {
  std::vector<long> sizes(tree.nodes.size(), 1);
  for (auto edge = tree.edges.rbegin(); edge != tree.edges.rend(); ++edge)
    sizes[static_cast<std::size_t>(edge->parent)] += sizes[static_cast<std::size_t>(edge->child)];
  return sizes;
}

TEST(TreePartition, EveryNodeIsInTheTrunkOrOneUnitSubtreeAndTheBoundMinimisesTheFarmPath) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const std::vector<long> parents = capture_like_parents(60 + 7 * seed, seed);
    const AlignmentTree tree = tree_of(parents);
    const TreePartition partition = partition_tree(tree);
    const std::vector<long> sizes = subtree_sizes(tree);
    ASSERT_EQ(partition.unit_of.size(), parents.size());
    EXPECT_TRUE(partition.in_trunk(0)) << "the root (the template) is in the trunk";
    std::vector<long> counted(static_cast<std::size_t>(partition.units()), 0);
    long trunk = 0;
    for (std::size_t node = 0; node < parents.size(); ++node) {
      const long unit = partition.unit_of[node];
      if (unit < 0) {
        ++trunk;
        if (node > 0) EXPECT_TRUE(partition.in_trunk(parents[node])) << "the trunk holds its nodes' parents";
        continue;
      }
      ASSERT_LT(unit, partition.units());
      ++counted[static_cast<std::size_t>(unit)];
      const bool root_of_unit = partition.unit_roots[static_cast<std::size_t>(unit)] == static_cast<long>(node);
      // A unit is a whole subtree: its root hangs from the trunk, every other node from the unit.
      EXPECT_EQ(partition.unit_of[static_cast<std::size_t>(parents[node])], root_of_unit ? -1 : unit) << node;
      if (root_of_unit) EXPECT_EQ(partition.unit_sizes[static_cast<std::size_t>(unit)], sizes[node]);
    }
    EXPECT_EQ(trunk, partition.trunk_size);
    EXPECT_EQ(counted, partition.unit_sizes);
    EXPECT_EQ(*std::max_element(counted.begin(), counted.end()), partition.bound);
    EXPECT_TRUE(std::is_sorted(partition.unit_roots.begin(), partition.unit_roots.end()));
    // No bound gives a shorter farm path (trunk + largest unit) or an equal one with a smaller trunk.
    for (long bound = 1; bound < static_cast<long>(parents.size()); ++bound) {
      long above = 0, largest = 0;
      for (std::size_t node = 1; node < parents.size(); ++node) {
        if (sizes[node] > bound) ++above;
        else largest = std::max(largest, sizes[node]);
      }
      const long cost = 1 + above + largest, best = partition.trunk_size + partition.bound;
      EXPECT_TRUE(cost > best || (cost == best && 1 + above >= partition.trunk_size)) << "seed " << seed << " bound " << bound;
    }
  }
}

TEST(TreePartition, TwoLongChainsAreTwoUnitsAndASingleNodeIsAllTrunk) {
  std::vector<long> parents = {-1};
  for (long k = 1; k <= 30; ++k) parents.push_back(k == 1 ? 0 : k - 1);   // chain of 30 from the root
  for (long k = 31; k <= 50; ++k) parents.push_back(k == 31 ? 0 : k - 1);  // chain of 20
  const TreePartition partition = partition_tree(tree_of(parents));
  EXPECT_EQ(partition.trunk_size, 1);
  EXPECT_EQ(partition.unit_roots, (std::vector<long>{1, 31}));
  EXPECT_EQ(partition.unit_sizes, (std::vector<long>{30, 20}));
  const TreePartition single = partition_tree(tree_of({-1}));
  EXPECT_EQ(single.trunk_size, 1);
  EXPECT_EQ(single.units(), 0);
  EXPECT_EQ(group_units(single, 3), (std::vector<std::vector<long>>{{}, {}, {}}));
}

TEST(TreePartition, JobGroupsHoldEveryUnitOnceAndAreBalanced) {
  const TreePartition partition = partition_tree(tree_of(capture_like_parents(300, 7)));
  ASSERT_GE(partition.units(), 8);
  const long total = std::accumulate(partition.unit_sizes.begin(), partition.unit_sizes.end(), 0L);
  for (int jobs = 1; jobs <= 12; ++jobs) {
    const auto groups = group_units(partition, jobs);
    ASSERT_EQ(groups.size(), static_cast<std::size_t>(jobs));
    EXPECT_EQ(groups, group_units(partition, jobs)) << "deterministic";
    std::vector<long> seen;
    long heaviest = 0;
    for (const auto& group : groups) {
      EXPECT_TRUE(std::is_sorted(group.begin(), group.end()));
      long load = 0;
      for (const long unit : group) load += partition.unit_sizes[static_cast<std::size_t>(unit)];
      heaviest = std::max(heaviest, load);
      seen.insert(seen.end(), group.begin(), group.end());
    }
    std::sort(seen.begin(), seen.end());
    std::vector<long> all(static_cast<std::size_t>(partition.units()));
    std::iota(all.begin(), all.end(), 0L);
    EXPECT_EQ(seen, all) << jobs << " jobs";
    // Largest first into the lightest group: no group exceeds the mean by more than one unit.
    EXPECT_LE(heaviest, (total + jobs - 1) / jobs + partition.bound) << jobs << " jobs";
    if (jobs == 1) EXPECT_EQ(heaviest, total);
  }
}

}  // namespace
}  // namespace surfcap::align
