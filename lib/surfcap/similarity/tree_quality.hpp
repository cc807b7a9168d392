#pragma once
// How good a similarity tree is for alignment, measured against ground truth: the true
// non-rigid deformation along its edges against the best possible tree's.

#include <Eigen/Core>

#include "surfcap/core/database.hpp"
#include "surfcap/similarity/similarity_files.hpp"

namespace surfcap::similarity {

/// N×N mean vertex distance between the true centred (root motion removed) template surfaces of
/// the frames in `frames`, looked up in `truth` by sequence name and frame offset.
/// bad_input if the truth lacks a sequence or frames.
Eigen::MatrixXd ground_truth_distances(const core::AlignedDatabase& truth, const FrameList& frames, int threads);

struct TreeQuality {
  double tree_deformation = 0;     ///< Σ true distance over the tree's edges (metres)
  double optimal_deformation = 0;  ///< the same for the minimum spanning tree of the true distances
  double ratio = 0;                ///< tree / optimal (≥ 1; 1 is perfect)
};

TreeQuality tree_quality(const SimilarityTree& tree, const Eigen::MatrixXd& true_distances);

}  // namespace surfcap::similarity
