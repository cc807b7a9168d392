#pragma once
// Colour maps for previews: heat maps on meshes (errors, weights) and matrix images
// (similarity matrices: blue similar → red dissimilar).

#include <Eigen/Core>

#include "surfcap/render/image.hpp"

namespace surfcap::render {

/// Blue (0) → cyan → green → yellow → red (1); values outside [0, 1] are clamped.
Eigen::Vector3d heat_color(double value);

/// Per-value colours (n×3, 0..1) mapping [low, high] onto heat_color; for per-vertex heat maps
/// (assign to Mesh::colors and render).
Eigen::MatrixXd heat_colors(const Eigen::VectorXd& values, double low, double high);

/// An image of a matrix, `cell` pixels per entry, entry (0, 0) at the top-left.
Image matrix_image(const Eigen::MatrixXd& values, double low, double high, int cell = 1);

}  // namespace surfcap::render
