#pragma once
// The exact non-linear blend of a character's motion spaces (blend::NonlinearBlender over the
// stored, time-warped references), for checking what the runtime plays: at a fractional frame
// f = k + α it is (1 − α)·b(M(k), w(u)) + α·b(M(k+1), w(u)), the same linear interpolation in time
// the runtime and the time warp use.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "surfcap/asset/character.hpp"
#include "surfcap/blend/nonlinear_blend.hpp"
#include "surfcap/runtime/space_evaluator.hpp"

namespace surfcap::runtime {

class ExactBlend {
 public:
  /// Factors the template and decomposes every reference frame of every space (threads: 0 = all).
  ExactBlend(const asset::Character& character, int threads = 0);
  ~ExactBlend();

  /// Centred V×3 mesh of space `space` at frame f and weight-space point u.
  Eigen::MatrixXd centred(int space, double frame, const std::vector<double>& u) const;

 private:
  const asset::Character* character_;
  std::unique_ptr<blend::NonlinearBlender> blender_;
  std::vector<std::vector<std::vector<blend::DecomposedFrame>>> decomposed_;  // [space][source][t]
  std::vector<std::unique_ptr<SpaceEvaluator>> evaluators_;
};

/// Max vertex distance between a V×3 float buffer and a V×3 matrix (metres).
double max_vertex_error(const std::vector<float>& mesh, const Eigen::MatrixXd& reference);

}  // namespace surfcap::runtime
