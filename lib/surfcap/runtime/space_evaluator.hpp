#pragma once
// Real-time evaluation of a parametric motion space M(t, p) (casas2013 §3.1, docs/runtime.md):
// u = h⁻¹(p), w = w(u), the linear blend of the 2^d sources plus the ≤ 2^d sparse float16
// displacement fields of u's grid cell (casas2011 eq. 3), linearly interpolated between the two
// normalised frames around t; and the blended root motion that places the mesh in the world.
// Everything is decoded at construction: evaluation reads memory only and allocates nothing.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "surfcap/asset/character.hpp"

namespace surfcap::runtime {

/// R_y(angle) (core::to_world's rotation about +y) applied to a ground-plane vector (x, z).
Eigen::Vector2d rotate_ground(const Eigen::Vector2d& v, double angle);

/// Time is a fractional normalised frame f: [0, T−1] for one-shot spaces, [0, T) for cyclic ones
/// (the step T−1 → 0 is one frame).
class SpaceEvaluator {
 public:
  explicit SpaceEvaluator(const asset::CharacterSpace& space);

  const asset::CharacterSpace& space() const { return *space_; }
  int dimensions() const { return space_->dimensions; }
  int frames() const { return space_->frames; }
  bool cyclic() const { return space_->cyclic; }
  long vertex_count() const { return vertices_; }
  /// Last reachable frame position: T−1 (one-shot) or just below T (cyclic, wraps).
  double end_frame() const { return cyclic() ? frames() : frames() - 1; }
  /// f wrapped into [0, T) for cyclic spaces, clamped to [0, T−1] otherwise.
  double wrap(double frame) const;

  /// High-level parameter range per axis ([0,1] per axis when the space has no parameter map).
  double parameter_min(int axis) const { return parameter_range_[axis][0]; }
  double parameter_max(int axis) const { return parameter_range_[axis][1]; }
  /// u = h⁻¹(p) in [0,1]^d (identity, clamped, without a parameter map).
  void weight_coordinates(const double* p, double* u) const;
  /// p with |h⁻¹(p) − u| smallest over a fine sampling of the parameter range (for reports and
  /// the precomputed-transition baseline, not the hot path).
  std::vector<double> parameters_for(const std::vector<double>& u) const;

  /// Normalised frames per output frame at u: (T − 1) / (Σ w_i duration_i · fps).
  double frames_per_step(const double* u, double fps) const;

  /// Centred mesh M(f, u) into `out` (V×3 floats, row-major).
  void evaluate(double frame, const double* u, float* out) const;

  /// Root motion from f0 to f1 (forward, wrapping in cyclic spaces) at u, in the body frame at f0:
  /// (forward x, z displacement in metres, heading change in radians); and the blended root height.
  Eigen::Vector3d root_step(double f0, double f1, const double* u) const;
  double root_height(double frame, const double* u) const;

  /// The grid cell of u: the ≤ 2^d (node, g_j) pairs with g_j > 0; returns their count.
  int cell_weights(const double* u, long* nodes, double* weights) const;
  /// Source weights w(u) (2^d, multilinear).
  void source_weights(const double* u, double* w) const;

 private:
  /// Σ_i w_i L_i(f): blended local root (forward x, height y, z, cumulative turn) at frame f ∈ [0, T].
  Eigen::Vector4d local_root(double frame, const double* w) const;

  const asset::CharacterSpace* space_;
  long vertices_ = 0;
  std::vector<float> displacement_values_;          // decoded float16
  std::vector<std::vector<Eigen::Vector4d>> local_roots_;  // [N][T + 1] relative to each source's first frame
  std::vector<std::array<double, 2>> parameter_range_;
};

}  // namespace surfcap::runtime
