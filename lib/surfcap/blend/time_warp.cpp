#include "surfcap/blend/time_warp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "surfcap/core/error.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::blend {

Eigen::MatrixXd pose_distance_matrix(const std::vector<Eigen::MatrixXd>& a, const std::vector<Eigen::MatrixXd>& b,
                                     long stride, int threads) {
  Eigen::MatrixXd cost(static_cast<long>(a.size()), static_cast<long>(b.size()));
  stride = std::max(1L, stride);
  core::parallel_for(cost.rows(), threads, [&](long i) {
    for (long j = 0; j < cost.cols(); ++j) {
      double sum = 0;
      long count = 0;
      for (long v = 0; v < a[i].rows(); v += stride, ++count) sum += (a[i].row(v) - b[j].row(v)).squaredNorm();
      cost(i, j) = sum / static_cast<double>(std::max(1L, count));
    }
  });
  return cost;
}

std::vector<std::pair<int, int>> dynamic_time_warp(const Eigen::MatrixXd& cost) {
  const long rows = cost.rows(), cols = cost.cols();
  if (rows == 0 || cols == 0) throw core::internal_error("dynamic_time_warp: empty cost matrix");
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd total = Eigen::MatrixXd::Constant(rows, cols, inf);
  for (long i = 0; i < rows; ++i)
    for (long j = 0; j < cols; ++j) {
      double best = (i == 0 && j == 0) ? 0.0 : inf;
      if (i > 0 && j > 0) best = std::min(best, total(i - 1, j - 1));
      if (i > 0) best = std::min(best, total(i - 1, j));
      if (j > 0) best = std::min(best, total(i, j - 1));
      total(i, j) = best + cost(i, j);
    }
  std::vector<std::pair<int, int>> path;
  long i = rows - 1, j = cols - 1;
  path.emplace_back(static_cast<int>(i), static_cast<int>(j));
  while (i > 0 || j > 0) {
    if (i > 0 && j > 0 && total(i - 1, j - 1) <= std::min(i > 0 ? total(i - 1, j) : inf, j > 0 ? total(i, j - 1) : inf)) {
      --i;
      --j;
    } else if (i > 0 && (j == 0 || total(i - 1, j) <= total(i, j - 1))) {
      --i;
    } else {
      --j;
    }
    path.emplace_back(static_cast<int>(i), static_cast<int>(j));
  }
  std::reverse(path.begin(), path.end());
  return path;
}

std::vector<std::vector<double>> time_warps(const std::vector<std::vector<Eigen::MatrixXd>>& sequences, int frames,
                                            int threads) {
  if (sequences.empty() || frames < 2) throw core::internal_error("time_warps: need sequences and ≥ 2 frames");
  const auto& reference = sequences.front();
  const long stride = std::max(1L, reference.front().rows() / 1000);
  const double reference_last = static_cast<double>(reference.size() - 1);
  std::vector<std::vector<double>> warps;
  for (const auto& sequence : sequences) {
    // Frame of `sequence` matched to each reference frame (mean over the DTW path).
    std::vector<double> matched(reference.size(), 0.0);
    std::vector<int> hits(reference.size(), 0);
    for (const auto& [r, s] : dynamic_time_warp(pose_distance_matrix(reference, sequence, stride, threads))) {
      matched[r] += s;
      ++hits[r];
    }
    for (std::size_t r = 0; r < matched.size(); ++r) matched[r] /= hits[r];
    // Cycle to cycle: the range's first and last frames are matched to each other exactly.
    matched.front() = 0.0;
    matched.back() = static_cast<double>(sequence.size() - 1);
    std::vector<double> warp(static_cast<std::size_t>(frames));
    for (int k = 0; k < frames; ++k) {
      const double r = reference_last * k / (frames - 1);
      const auto lower = static_cast<std::size_t>(std::floor(r));
      const std::size_t upper = std::min(lower + 1, matched.size() - 1);
      warp[k] = matched[lower] + (r - lower) * (matched[upper] - matched[lower]);
    }
    warps.push_back(std::move(warp));
  }
  return warps;
}

Eigen::MatrixXd sample_frame(const std::vector<Eigen::MatrixXd>& frames, double frame) {
  frame = std::clamp(frame, 0.0, static_cast<double>(frames.size() - 1));
  const auto lower = static_cast<std::size_t>(std::floor(frame));
  const std::size_t upper = std::min(lower + 1, frames.size() - 1);
  const double f = frame - lower;
  if (f == 0.0) return frames[lower];
  return (1 - f) * frames[lower] + f * frames[upper];
}

core::RootMotion sample_root(const std::vector<core::RootMotion>& roots, double frame) {
  frame = std::clamp(frame, 0.0, static_cast<double>(roots.size() - 1));
  const auto lower = static_cast<std::size_t>(std::floor(frame));
  const std::size_t upper = std::min(lower + 1, roots.size() - 1);
  const double f = frame - lower;
  const core::RootMotion& a = roots[lower];
  const core::RootMotion& b = roots[upper];
  // Heading along the shorter way round.
  const double turn = std::remainder(b.heading - a.heading, 2 * M_PI);
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z), a.heading + f * turn};
}

}  // namespace surfcap::blend
