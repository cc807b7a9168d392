#include "surfcap/similarity/similarity_matrix.hpp"

#include <atomic>

#include "surfcap/core/error.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::similarity {

FrameIndex::FrameIndex(std::vector<int> sequence_lengths) : lengths_(std::move(sequence_lengths)) {
  for (std::size_t s = 0; s < lengths_.size(); ++s) {
    starts_.push_back(total_);
    for (int f = 0; f < lengths_[s]; ++f) sequence_.push_back(static_cast<int>(s));
    total_ += lengths_[s];
  }
}

bool FrameIndex::shift_valid(long frame, int k) const {
  const long offset = offset_in_sequence(frame) + k;
  return offset >= 0 && offset < length(sequence_of(frame));
}

Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> similarity_rows(
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& histograms,
    const ShapeHistogramOptions& layout, const FrameIndex& index, long row_begin, long row_end,
    const SimilarityOptions& options, const core::ProgressCallback& progress) {
  const long n = index.frames();
  if (histograms.rows() != n || histograms.cols() != layout.size())
    throw core::internal_error("similarity_rows: histograms do not match the frame index or the layout");
  if (row_begin < 0 || row_end > n || row_begin >= row_end)
    throw core::bad_arguments("row block " + std::to_string(row_begin) + ":" + std::to_string(row_end) +
                              " is outside 0:" + std::to_string(n));
  const int w = options.temporal_window;
  // Static distances for every row the filter of this block touches.
  const long static_begin = std::max(0L, row_begin - w), static_end = std::min(n, row_end + w);
  Eigen::MatrixXd distances(static_end - static_begin, n);
  std::atomic<std::size_t> done{0};
  const std::size_t total = static_cast<std::size_t>(static_end - static_begin);
  core::parallel_for(static_end - static_begin, options.threads, [&](long r) {
    const long i = static_begin + r;
    for (long j = 0; j < n; ++j)
      distances(r, j) = i == j ? 0.0 : match_histograms(histograms.row(i).data(), histograms.row(j).data(), layout,
                                                         options.rotation_search).distance;
    if (progress) progress(++done, total);
  });
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows(row_end - row_begin, n);
  for (long i = row_begin; i < row_end; ++i) {
    for (long j = 0; j < n; ++j) {
      double sum = 0;
      int count = 0;
      for (int k = -w; k <= w; ++k) {
        if (!index.shift_valid(i, k) || !index.shift_valid(j, k)) continue;
        sum += distances(i + k - static_begin, j + k);
        ++count;
      }
      rows(i - row_begin, j) = static_cast<float>(sum / count);  // k = 0 is always valid
    }
  }
  return rows;
}

}  // namespace surfcap::similarity
