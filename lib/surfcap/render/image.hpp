#pragma once
// An 8-bit RGB image: what the renderer produces and PNG files hold.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace surfcap::render {

/// Row-major, 3 bytes per pixel (R, G, B), origin at the top-left corner.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;

  Image() = default;
  /// A width×height image filled with `color` (0..1 per channel).
  Image(int width, int height, const Eigen::Vector3d& color = Eigen::Vector3d::Zero());

  bool empty() const { return width == 0 || height == 0; }
  std::uint8_t* at(int x, int y) { return pixels.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
  const std::uint8_t* at(int x, int y) const { return pixels.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
  /// Colour of pixel (x, y) in 0..1.
  Eigen::Vector3d get(int x, int y) const;
  /// Sets pixel (x, y) from a 0..1 colour (clamped, rounded).
  void set(int x, int y, const Eigen::Vector3d& color);
  /// Copies `source` with its top-left corner at (x, y), clipped to this image.
  void paste(const Image& source, int x, int y);
};

/// 0..1 → 0..255, clamped and rounded.
std::uint8_t to_byte(double value);

}  // namespace surfcap::render
