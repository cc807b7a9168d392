#include "surfcap/render/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace surfcap::render {

Eigen::Vector3d heat_color(double value) {
  static const std::array<Eigen::Vector3d, 5> stops = {
      Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(0.0, 1.0, 1.0), Eigen::Vector3d(0.0, 1.0, 0.0),
      Eigen::Vector3d(1.0, 1.0, 0.0), Eigen::Vector3d(1.0, 0.0, 0.0)};
  const double x = std::isfinite(value) ? std::clamp(value, 0.0, 1.0) * 4.0 : 0.0;
  const int i = std::min(3, static_cast<int>(x));
  const double s = x - i;
  return (1 - s) * stops[static_cast<std::size_t>(i)] + s * stops[static_cast<std::size_t>(i + 1)];
}

Eigen::MatrixXd heat_colors(const Eigen::VectorXd& values, double low, double high) {
  Eigen::MatrixXd colors(values.size(), 3);
  const double range = high > low ? high - low : 1.0;
  for (long i = 0; i < values.size(); ++i) colors.row(i) = heat_color((values[i] - low) / range).transpose();
  return colors;
}

Image matrix_image(const Eigen::MatrixXd& values, double low, double high, int cell) {
  Image image(static_cast<int>(values.cols()) * cell, static_cast<int>(values.rows()) * cell);
  const double range = high > low ? high - low : 1.0;
  for (long r = 0; r < values.rows(); ++r)
    for (long c = 0; c < values.cols(); ++c) {
      const Eigen::Vector3d color = heat_color((values(r, c) - low) / range);
      for (int dy = 0; dy < cell; ++dy)
        for (int dx = 0; dx < cell; ++dx)
          image.set(static_cast<int>(c) * cell + dx, static_cast<int>(r) * cell + dy, color);
    }
  return image;
}

}  // namespace surfcap::render
