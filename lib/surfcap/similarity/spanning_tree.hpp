#pragma once
// The shape similarity tree (casas2011 §3.1): the minimum spanning tree of the graph of all
// frames, its edges pruned above the automatic threshold, rooted to minimise the total
// cost-weighted depth (the alignment error accumulates along the path from the root).

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace surfcap::similarity {

struct TreeEdge {
  int parent = 0;
  int child = 0;
  double cost = 0;
};

struct SimilarityTree {
  int root = 0;
  double threshold = 0;             ///< s_min as a dissimilarity: the largest per-row best match
  int components_after_pruning = 1; ///< > 1: pruning disconnected the graph
  int joining_edges = 0;            ///< edges above the threshold added to reconnect it
  std::vector<TreeEdge> edges;      ///< breadth-first from the root: every parent precedes its children
  std::vector<int> depth;           ///< per node, in edges from the root
  double total_cost = 0;
  double weighted_depth = 0;        ///< Σ over nodes of the path cost from the root
};

using FloatRows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The automatic threshold: max over rows of the smallest off-diagonal entry.
double automatic_threshold(const Eigen::MatrixXd& costs);
double automatic_threshold(const FloatRows& costs);

/// Builds the tree from a symmetric N×N cost matrix (the filtered dissimilarity; only the upper
/// triangle is read after symmetrising). `root`: a given root node, else the one of minimal
/// weighted depth among `eligible_roots` (N flags; empty: every node). Ties are broken by node
/// order, so the result is deterministic. Time O(N²), memory O(N) beyond the costs; the float
/// form (similarity/matrix.npy as read) gives the same tree as its double copy.
SimilarityTree similarity_tree(const Eigen::MatrixXd& costs, std::optional<int> root = std::nullopt,
                               std::optional<double> threshold = std::nullopt,
                               const std::vector<bool>& eligible_roots = {});
SimilarityTree similarity_tree(const FloatRows& costs, std::optional<int> root = std::nullopt,
                               std::optional<double> threshold = std::nullopt,
                               const std::vector<bool>& eligible_roots = {});

/// The automatic template candidates: the frames whose stance (stance_width of their mesh) is in
/// the widest `fraction` of all frames (at least one). An open pose — feet apart — makes a better
/// template than a closed one: aligning legs together → apart lays one leg onto the other, the
/// reverse does not. Empty `stance`: no restriction (empty result).
std::vector<bool> wide_stance_roots(const std::vector<double>& stance, double fraction = 0.25);

/// Minimum spanning tree total cost of a complete graph (no pruning), for evaluation.
double minimum_spanning_tree_cost(const Eigen::MatrixXd& costs);

}  // namespace surfcap::similarity
