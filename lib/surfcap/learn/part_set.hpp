#pragma once
// Part decompositions (tejera2013 §IV-A): overlapping vertex sets with a hierarchy rooted at the
// torso, defined by a parts config (configs/parts/*.json) whose rules survive remeshing.
#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"

namespace surfcap::learn {

/// One part: a set of template vertices and its parent in the hierarchy (−1 for the root).
struct Part {
  std::string name;
  int parent = -1;
  std::vector<int> vertices;  ///< sorted template vertex indices
  std::vector<int> frontier;  ///< vertices shared with the parent (sorted, ⊂ vertices); empty for the root
};

/// Parts in hierarchy order (every parent before its children; parts[0] is the root) plus
/// named vertex regions (hands, feet, head...) that edits and evaluations refer to.
struct PartSet {
  std::vector<Part> parts;
  std::map<std::string, std::vector<int>> regions;
  int find(const std::string& name) const;  ///< −1 if absent
};

/// Sorts parts so parents come first, fills frontiers from vertex sharing and checks the
/// hierarchy (one root, known parents, every child overlapping its parent, every vertex in some
/// part). Throws bad_input naming `source`.
void finalise_hierarchy(PartSet& parts, long vertex_count, const std::filesystem::path& source);

/// Builds the tree by vertex sharing: the root is `root` (or the largest part when empty); each
/// other part's parent is the part, closer to the root, it shares most vertices with.
void build_hierarchy_by_sharing(PartSet& parts, const std::string& root, long vertex_count);

/// The five extremities of a human-like template (geodesic farthest points from the body
/// centre), named head, hand_l, hand_r, foot_l, foot_r (_l is the +x side), and the centre.
struct Extremities {
  int centre = -1;
  std::map<std::string, int> vertices;
  std::map<std::string, double> reach;  ///< geodesic distance extremity → centre (metres)
};
Extremities find_extremities(const core::Mesh& mesh);

/// Evaluates a parts config (format surfcap.part_config/1, docs/learn.md) on `mesh` (the
/// template in its rest pose). Parts are given by explicit vertex lists or by rules
/// ("extremity" + "extent" + "overlap_rings", or "rest": the complement of the other parts'
/// cores grown by nothing). Throws bad_input naming `source`.
PartSet evaluate_part_config(const core::Json& config, const core::Mesh& mesh, const std::filesystem::path& source);
PartSet read_part_config(const std::filesystem::path& path, const core::Mesh& mesh);

/// An editable parts config holding explicit vertex lists (what `surfcap-learn parts` writes).
core::Json part_config_with_vertex_lists(const PartSet& parts);

/// Per-vertex blend weight of `part` over its frontier: 1 inside the part away from the parent,
/// falling linearly to 0 at the frontier vertices farthest (in rings) from the part's own region.
Eigen::VectorXd frontier_blend_weights(const Part& part, const std::vector<std::vector<int>>& adjacency);

}  // namespace surfcap::learn
