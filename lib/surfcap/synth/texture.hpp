#pragma once
// The actor's procedural surface texture: per-region base colours with a solid texture of
// high-contrast discs and rotated squares (blobs and corners for SIFT), evaluated at rest-pose
// coordinates so it is fixed to the body surface and moves with it.

#include <Eigen/Core>
#include <cstdint>

#include "surfcap/synth/body.hpp"

namespace surfcap::synth {

class BodyTexture {
 public:
  /// `feature_size`: spacing of the pattern's cells, metres.
  explicit BodyTexture(std::uint64_t seed, double feature_size = 0.05);
  /// Albedo (0..1) at rest-pose point `rest_point` on a surface of `region`.
  Eigen::Vector3d color(const Eigen::Vector3d& rest_point, Region region) const;

 private:
  std::uint64_t seed_;
  double cell_;
};

/// Albedo at face `face`, barycentric `b` of `body.rest` (region of the nearest corner).
Eigen::Vector3d surface_albedo(const Body& body, const BodyTexture& texture, long face, const Eigen::Vector3d& b);

/// Per-vertex albedo of the rest template (V×3).
Eigen::MatrixXd vertex_albedo(const Body& body, const BodyTexture& texture);

}  // namespace surfcap::synth
