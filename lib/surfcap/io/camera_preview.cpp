#include "surfcap/io/camera_preview.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace surfcap::io {

render::Image camera_layout_preview(const std::vector<core::CaptureCamera>& cameras, int size) {
  // Extent: the origin and every camera centre, with a margin.
  double extent = 1.0;
  for (const auto& camera : cameras) {
    const Eigen::Vector3d centre = -camera.R.transpose() * camera.t;
    extent = std::max({extent, std::abs(centre.x()), std::abs(centre.z())});
  }
  const double scale = 0.42 * size / extent;  // pixels per metre
  auto pixel = [&](double x, double z) {
    return cv::Point(static_cast<int>(std::lround(0.5 * size + scale * x)), static_cast<int>(std::lround(0.5 * size + scale * z)));
  };
  cv::Mat canvas(size, size, CV_8UC3, cv::Scalar(245, 245, 245));
  const cv::Scalar grey(150, 150, 150), ink(40, 40, 40), blue(200, 90, 30);  // BGR
  cv::line(canvas, pixel(-0.1, 0), pixel(0.1, 0), grey, 1, cv::LINE_AA);
  cv::line(canvas, pixel(0, -0.1), pixel(0, 0.1), grey, 1, cv::LINE_AA);
  cv::line(canvas, cv::Point(12, size - 14), cv::Point(12 + static_cast<int>(std::lround(scale)), size - 14), ink, 2);
  cv::putText(canvas, "1 m", cv::Point(14, size - 20), cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
  cv::putText(canvas, "top view: x right, z down", cv::Point(10, 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
  for (const auto& camera : cameras) {
    const Eigen::Vector3d centre = -camera.R.transpose() * camera.t;
    const Eigen::Vector3d forward = camera.R.row(2).transpose();
    const Eigen::Vector2d direction = Eigen::Vector2d(forward.x(), forward.z()).normalized() * (0.12 * size / scale);
    const cv::Point at = pixel(centre.x(), centre.z());
    if (std::isfinite(direction.x()))
      cv::arrowedLine(canvas, at, pixel(centre.x() + direction.x(), centre.z() + direction.y()), blue, 2, cv::LINE_AA, 0, 0.2);
    cv::circle(canvas, at, 5, ink, cv::FILLED, cv::LINE_AA);
    int baseline = 0;
    const cv::Size text = cv::getTextSize(camera.name, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline);
    const cv::Point label(std::clamp(at.x + 8, 2, size - text.width - 2), std::clamp(at.y - 8, text.height + 2, size - 2));
    cv::putText(canvas, camera.name, label, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
  }
  render::Image image(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const cv::Vec3b& p = canvas.at<cv::Vec3b>(y, x);
      std::uint8_t* out = image.at(x, y);
      out[0] = p[2], out[1] = p[1], out[2] = p[0];
    }
  return image;
}

}  // namespace surfcap::io
