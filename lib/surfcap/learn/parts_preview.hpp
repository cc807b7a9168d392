#pragma once
// A PNG preview of the parts coloured on the template (front and side orthographic views).
#include <filesystem>

#include "surfcap/learn/part_set.hpp"

namespace surfcap::learn {

/// Each part gets a colour; overlap vertices mix their parts' colours. Triangles are rasterised
/// with a z-buffer and flat Lambert shading (OpenCV, no render module needed). Written atomically.
void write_parts_preview(const std::filesystem::path& png, const core::Mesh& mesh, const PartSet& parts,
                         int height = 512);

}  // namespace surfcap::learn
