#pragma once
// PNG previews of the similarity stage.

#include <Eigen/Core>
#include <filesystem>

#include "surfcap/similarity/similarity_matrix.hpp"
#include "surfcap/similarity/spanning_tree.hpp"

namespace surfcap::similarity {

/// Heat map of the N×N dissimilarity (blue similar → red dissimilar, scaled to the 99th
/// percentile), white lines at sequence borders, and, when `tree` is given, its edges as black
/// dots at (parent, child) and (child, parent) with the root's row and column marked.
/// At least 512 pixels wide (cells are enlarged for small N); beyond 2,048 frames a pixel shows
/// the mean of a k×k block of frames (k = ⌈N / 2048⌉), so the preview's memory stays bounded.
/// Written atomically.
void write_similarity_png(const std::filesystem::path& path, const FloatRows& matrix, const FrameIndex& index,
                          const SimilarityTree* tree = nullptr);

}  // namespace surfcap::similarity
