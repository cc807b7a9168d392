#pragma once
// The sources of a motion space after time warping: N = 2^d sequences of T frames each, placed
// at the corners of the weight space [0,1]^d. Source i sits at the corner whose coordinate a is
// bit a of i (d = 1: i = 0 at u = 0, i = 1 at u = 1; d = 2: 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1)).
#include <Eigen/Core>
#include <vector>

#include "surfcap/blend/nonlinear_blend.hpp"

namespace surfcap::blend {

/// Multilinear weights of the 2^d corners at u ∈ [0,1]^d (they sum to one).
std::vector<double> corner_weights(const std::vector<double>& u);

/// d such that 2^d = source_count; throws bad_arguments otherwise (N ∈ {2, 4, 8}).
int weight_space_dimensions(int source_count);

class SourceSet {
 public:
  /// `frames[i][t]`: V×3 centred positions of source i at normalised frame t (same T for all).
  /// Decomposes every frame once (parallel over frames, `threads`).
  SourceSet(const NonlinearBlender& blender, std::vector<std::vector<Eigen::MatrixXd>> frames, int threads = 1);

  int source_count() const { return static_cast<int>(frames_.size()); }
  int dimensions() const { return dimensions_; }
  int frame_count() const { return static_cast<int>(frames_.front().size()); }
  long vertex_count() const { return frames_.front().front().rows(); }
  const Eigen::MatrixXd& frame(int source, int t) const { return frames_[source][t]; }
  const NonlinearBlender& blender() const { return *blender_; }

  /// M_L(t, w(u)).
  void linear_into(int t, const std::vector<double>& u, Eigen::MatrixXd& result) const;
  Eigen::MatrixXd linear(int t, const std::vector<double>& u) const;
  /// M_NL(t, w(u)) = b(M(t), w(u)); exactly the source at the corners.
  Eigen::MatrixXd exact(int t, const std::vector<double>& u, int threads = 1) const;

 private:
  const NonlinearBlender* blender_;
  std::vector<std::vector<Eigen::MatrixXd>> frames_;
  std::vector<std::vector<DecomposedFrame>> decomposed_;
  int dimensions_ = 1;
};

}  // namespace surfcap::blend
