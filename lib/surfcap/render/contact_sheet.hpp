#pragma once
// A grid of images with captions: how a person looks at many frames or views at once.

#include <string>
#include <vector>

#include "surfcap/render/image.hpp"

namespace surfcap::render {

struct ContactSheetOptions {
  int columns = 4;
  int padding = 4;                        ///< pixels between and around cells
  Eigen::Vector3d background{0.15, 0.15, 0.15};
  double scale = 1.0;                     ///< cells are resized by this factor
  std::vector<std::string> labels;        ///< one caption per image (may be shorter / empty)
};

/// Images laid out row by row; each cell is as large as the largest image (after scaling).
Image contact_sheet(const std::vector<Image>& images, const ContactSheetOptions& options = {});

}  // namespace surfcap::render
