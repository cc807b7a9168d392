#pragma once
// The contact sheet of surfcap-play: sampled frames rendered from a camera that follows the
// character, coloured by motion space (hue) and parameter (lightness), as casas2013 Fig. 8 does.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "surfcap/core/mesh.hpp"
#include "surfcap/render/image.hpp"

namespace surfcap::runtime {

struct PreviewFrame {
  Eigen::MatrixXd world;  ///< V×3 world positions
  int space = 0;
  double parameter = 0.5;  ///< first weight-space coordinate u_0 ∈ [0, 1]
  std::string label;
};

/// Colour of a frame: one hue per space, darker for low u_0, lighter for high.
Eigen::Vector3d space_colour(int space, double parameter);

/// Renders every frame (template connectivity) into a grid of `columns` cells.
render::Image play_contact_sheet(const core::Mesh& template_mesh, const std::vector<PreviewFrame>& frames,
                                 int columns = 6);

}  // namespace surfcap::runtime
