#pragma once
// What the ground-truth evaluation of an alignment writes besides its figures: the per-vertex
// error arrays (for analysis outside surfcap) and a preview of the frames worst against the truth.

#include <filesystem>
#include <vector>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/evaluation/ground_truth_error.hpp"

namespace surfcap::evaluation {

/// <folder>/truth_errors.npy (float32 [nodes, n, 3]: aligned − true world position per template
/// vertex, nodes in report order) and truth_observed.npy (uint8 [nodes, n]: 1 where a camera of
/// the capture sees the true location).
void write_truth_arrays(const std::filesystem::path& folder, const TruthReference& truth,
                        const align::Registration& registration, const TruthEvaluation& evaluation);

/// The `count` nodes with the largest RMS error against the truth, worst first (ties: lower node).
std::vector<long> worst_frames(const TruthEvaluation& evaluation, int count);

/// The worst frames (worst_frames) front and side, coloured by each vertex's distance from its
/// true position (blue 0 → red `scale` metres).
void write_truth_preview(const std::filesystem::path& path, const TruthReference& truth,
                         const align::Registration& registration, const TruthEvaluation& evaluation, int count,
                         double scale);

}  // namespace surfcap::evaluation
