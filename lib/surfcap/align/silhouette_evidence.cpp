#include "surfcap/align/silhouette_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "surfcap/render/rasterizer.hpp"

namespace surfcap::align {

namespace {

/// `camera` with its image scaled by `scale` (pixel centres stay at integer coordinates).
render::Camera scaled(const render::Camera& camera, double scale) {
  render::Camera result = camera;
  result.width = std::max(1, static_cast<int>(std::lround(camera.width * scale)));
  result.height = std::max(1, static_cast<int>(std::lround(camera.height * scale)));
  const double sx = static_cast<double>(result.width) / camera.width;
  const double sy = static_cast<double>(result.height) / camera.height;
  result.K.row(0) *= sx;
  result.K.row(1) *= sy;
  result.K(0, 2) += 0.5 * sx - 0.5;
  result.K(1, 2) += 0.5 * sy - 0.5;
  return result;
}

}  // namespace

SilhouetteEvidence::SilhouetteEvidence(const std::vector<render::Camera>& cameras, const Eigen::MatrixXd& V,
                                       const Eigen::MatrixXi& F, double gate)
    : gate_(gate) {
  for (const render::Camera& full : cameras) {
    const double scale = std::min(1.0, static_cast<double>(kMaxSide) / std::max(full.width, full.height));
    View view{scaled(full, scale), {}};
    const int width = view.camera.width, height = view.camera.height;
    const render::Visibility seen = render::render_visibility(V, F, view.camera);
    cv::Mat outside(height, width, CV_8U);
    bool any = false;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const bool inside = seen.face[static_cast<std::size_t>(y) * width + x] >= 0;
        outside.at<unsigned char>(y, x) = inside ? 0 : 255;
        any = any || inside;
      }
    if (!any) continue;  // the surface is not in this camera's image: it tells nothing
    cv::Mat distance;
    cv::distanceTransform(outside, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    view.distance.assign(distance.begin<float>(), distance.end<float>());
    views_.push_back(std::move(view));
  }
}

bool SilhouetteEvidence::outside(const Eigen::Vector3d& x) const {
  if (views_.empty()) return true;
  for (const View& view : views_) {
    const double z = view.camera.to_camera(x).z();
    if (!(z > 0)) continue;
    const Eigen::Vector2d p = view.camera.project(x);
    const long px = std::lround(p.x()), py = std::lround(p.y());
    if (px < 0 || py < 0 || px >= view.camera.width || py >= view.camera.height) continue;
    const double gate_px = gate_ * view.camera.K(0, 0) / z;
    if (view.distance[static_cast<std::size_t>(py * view.camera.width + px)] > gate_px) return true;
  }
  return false;
}

}  // namespace surfcap::align
