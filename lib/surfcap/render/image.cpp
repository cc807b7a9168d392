#include "surfcap/render/image.hpp"

#include <algorithm>
#include <cmath>

namespace surfcap::render {

std::uint8_t to_byte(double value) {
  if (!(value > 0)) return 0;
  return static_cast<std::uint8_t>(std::lround(std::min(value, 1.0) * 255.0));
}

Image::Image(int width_, int height_, const Eigen::Vector3d& color) : width(width_), height(height_) {
  pixels.resize(static_cast<std::size_t>(width) * height * 3);
  const std::uint8_t rgb[3] = {to_byte(color.x()), to_byte(color.y()), to_byte(color.z())};
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = rgb[i % 3];
}

Eigen::Vector3d Image::get(int x, int y) const {
  const std::uint8_t* p = at(x, y);
  return Eigen::Vector3d(p[0], p[1], p[2]) / 255.0;
}

void Image::set(int x, int y, const Eigen::Vector3d& color) {
  std::uint8_t* p = at(x, y);
  p[0] = to_byte(color.x());
  p[1] = to_byte(color.y());
  p[2] = to_byte(color.z());
}

void Image::paste(const Image& source, int x0, int y0) {
  for (int y = std::max(0, y0); y < std::min(height, y0 + source.height); ++y) {
    const int x_begin = std::max(0, x0), x_end = std::min(width, x0 + source.width);
    if (x_end <= x_begin) continue;
    std::copy_n(source.at(x_begin - x0, y - y0), static_cast<std::size_t>(x_end - x_begin) * 3, at(x_begin, y));
  }
}

}  // namespace surfcap::render
