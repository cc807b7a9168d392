#pragma once
// The registration jobs' partition of the similarity tree (docs/pipelines.md "Registration
// jobs"): a trunk holding the root, and unit subtrees hanging from it. It depends on the tree
// alone — never on the job or thread count — so the candidate parents a frame may use (its own
// unit and the trunk; a trunk frame only the trunk) and with them the output are the same however
// the units are spread over jobs.

#include <vector>

namespace surfcap::align {

struct AlignmentTree;

struct TreePartition {
  std::vector<long> unit_of;     ///< per node: its unit, −1 for a trunk node
  std::vector<long> unit_roots;  ///< per unit: its root node (units in ascending root order)
  std::vector<long> unit_sizes;  ///< per unit: its node count
  long trunk_size = 0;
  long bound = 0;                ///< B: no unit has more nodes

  long units() const { return static_cast<long>(unit_roots.size()); }
  bool in_trunk(long node) const { return unit_of[static_cast<std::size_t>(node)] < 0; }
};

/// The trunk is the root and every node whose subtree has more than B nodes; each node outside it
/// whose parent is in it roots a unit (its whole subtree). B is the subtree size that minimises
/// trunk nodes + B, the frames on the longest chain of jobs of a farm (trunk, then the largest
/// unit); ties go to the larger B (the smaller trunk).
TreePartition partition_tree(const AlignmentTree& tree);

/// The units in `jobs` groups balanced by node count: the largest unit first (ties: the lower
/// root node) into the group with the fewest nodes so far (ties: the lower group). Each group's
/// units in ascending order; a group is empty when there are fewer units than jobs.
std::vector<std::vector<long>> group_units(const TreePartition& partition, int jobs);

}  // namespace surfcap::align
