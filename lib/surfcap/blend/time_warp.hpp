#pragma once
// Time warping of the sequences of a motion space to a common normalised time t ∈ [0,1]
// (casas2011 §4): dynamic time warping on pose distance between centred frames (root motion
// removed). The sequences' frame ranges are the cycles to align, so cyclic motions align cycle
// to cycle (first frame ↔ first frame, last ↔ last).
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "surfcap/core/database.hpp"

namespace surfcap::blend {

/// Mean squared vertex distance between every frame of `a` (rows) and of `b` (columns), on every
/// `stride`-th vertex.
Eigen::MatrixXd pose_distance_matrix(const std::vector<Eigen::MatrixXd>& a, const std::vector<Eigen::MatrixXd>& b,
                                     long stride = 1, int threads = 1);

/// Minimum-cost monotone path through `cost` from (0,0) to (rows−1, cols−1) with steps
/// (1,0), (0,1), (1,1); ties prefer the diagonal, so the path is deterministic.
std::vector<std::pair<int, int>> dynamic_time_warp(const Eigen::MatrixXd& cost);

/// warps[i][k]: fractional frame of sequence i shown at normalised frame k (t = k/(frames−1)).
/// Sequence 0 is the reference, sampled uniformly; each other sequence follows its DTW path to
/// the reference (the mean of the frames matched to each reference frame), so warps are
/// non-decreasing and start/end at the first/last frame.
std::vector<std::vector<double>> time_warps(const std::vector<std::vector<Eigen::MatrixXd>>& sequences, int frames,
                                            int threads = 1);

/// Linear interpolation of a sequence at a fractional frame (clamped to the sequence).
Eigen::MatrixXd sample_frame(const std::vector<Eigen::MatrixXd>& frames, double frame);
core::RootMotion sample_root(const std::vector<core::RootMotion>& roots, double frame);

}  // namespace surfcap::blend
