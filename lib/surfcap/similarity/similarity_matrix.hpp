#pragma once
// Temporally filtered shape dissimilarity between all frames of all sequences (casas2011 §3.1,
// Huang et al. 2010): c(i, j) = mean over k ∈ [-w, w] of d(i+k, j+k), where d is the rotation-
// invariant histogram distance and the window is clipped where either frame would leave its
// sequence. 0 means identical; the matrix is what surfcap calls the similarity matrix.

#include <Eigen/Core>
#include <vector>

#include "surfcap/core/progress.hpp"
#include "surfcap/similarity/shape_histogram.hpp"

namespace surfcap::similarity {

/// Which sequence each of the N frames (all sequences, in order) belongs to.
class FrameIndex {
 public:
  explicit FrameIndex(std::vector<int> sequence_lengths);
  long frames() const { return total_; }
  int sequence_of(long frame) const { return sequence_[static_cast<std::size_t>(frame)]; }
  long offset_in_sequence(long frame) const { return frame - starts_[static_cast<std::size_t>(sequence_of(frame))]; }
  long start(int sequence) const { return starts_[static_cast<std::size_t>(sequence)]; }
  int length(int sequence) const { return lengths_[static_cast<std::size_t>(sequence)]; }
  int sequences() const { return static_cast<int>(lengths_.size()); }
  /// True when frame + k stays inside frame's sequence.
  bool shift_valid(long frame, int k) const;

 private:
  std::vector<int> lengths_;
  std::vector<long> starts_;
  std::vector<int> sequence_;
  long total_ = 0;
};

struct SimilarityOptions {
  int temporal_window = 2;  ///< w: frames on each side averaged by the temporal filter (0: static shape only)
  RotationSearch rotation_search = RotationSearch::fft;
  int threads = 0;
};

/// Rows [row_begin, row_end) of the N×N filtered matrix from float32 histograms (N×B, row-major
/// as stored in histograms.npy). Each value depends only on the histograms, never on the block
/// or the thread count, so blocks joined give the matrix computed whole, byte for byte.
Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> similarity_rows(
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& histograms,
    const ShapeHistogramOptions& layout, const FrameIndex& index, long row_begin, long row_end,
    const SimilarityOptions& options, const core::ProgressCallback& progress = {});

}  // namespace surfcap::similarity
