#pragma once
// Which reconstruction points show the aligned template is missing something, by the cameras'
// silhouettes. A reconstruction carved from silhouettes (a visual hull) keeps phantom volume that
// no camera can carve away: every point of it projects inside every camera's silhouette. Such a
// point, far from the aligned template, is no evidence of a part the template left behind when it
// also lies inside the template's own silhouette in every camera — the template's visual hull
// holds all the phantom volume of a correctly aligned template. A limb the template left behind
// lies outside the template's silhouette in some camera. This needs only the calibration, not the
// images. OpenCV stays inside silhouette_evidence.cpp.

#include <Eigen/Core>

#include <vector>

#include "surfcap/render/camera.hpp"

namespace surfcap::align {

class SilhouetteEvidence {
 public:
  /// Longest image side (pixels) the silhouettes are rendered at (the cameras are scaled down).
  static constexpr int kMaxSide = 512;

  /// The silhouettes of the surface (V, F) in every camera, to be compared with `gate` (metres).
  SilhouetteEvidence(const std::vector<render::Camera>& cameras, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     double gate);
  /// Does some camera see `x` (in front of it, inside its image) farther than `gate` (at x's
  /// depth) outside the surface's silhouette? Then x is farther than `gate` from the surface.
  /// True as well when no camera has the surface in its image: a calibration that does not see
  /// the body (another frame of reference) tells nothing, and every far point counts.
  bool outside(const Eigen::Vector3d& x) const;

 private:
  struct View {
    render::Camera camera;          ///< scaled to the rendered size
    std::vector<float> distance;    ///< pixels to the nearest silhouette pixel (0 inside)
  };
  std::vector<View> views_;
  double gate_ = 0;
};

}  // namespace surfcap::align
