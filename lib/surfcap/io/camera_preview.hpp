#pragma once
// A picture of a calibration: where the cameras stand and where they look, seen from above.

#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/render/image.hpp"

namespace surfcap::io {

/// Top view (looking down −y; x to the right, z down the image) of the camera centres with their
/// names and viewing directions, the world origin as a cross and a 1 m scale bar; size × size px.
render::Image camera_layout_preview(const std::vector<core::CaptureCamera>& cameras, int size = 640);

}  // namespace surfcap::io
