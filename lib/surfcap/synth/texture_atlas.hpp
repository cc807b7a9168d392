#pragma once
// A studio's textured mesh: charts of faces that one camera sees best, each chart's UVs its
// projection into that camera, the charts packed into one atlas whose texels are resampled from
// the camera images; written as a standard OBJ + MTL + PNG.

#include <filesystem>
#include <vector>

#include "surfcap/core/mesh.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/render/image.hpp"

namespace surfcap::synth {

struct TexturedMesh {
  core::Mesh mesh;                 ///< V, F; colors: per vertex, the atlas texel at its UVs
  Eigen::MatrixXd uv;              ///< texture coordinates (OBJ convention: v up, 0..1)
  Eigen::MatrixXi FT;              ///< per face corner: its row of uv (faces of several charts meet at seams)
  render::Image atlas;
  long charts = 0;
  long conflicting_corners = 0;    ///< corners whose texel another vertex's colour took
};

/// Bakes the texture of `mesh` from `images` (one per camera, the frame's camera images) with the
/// per-face camera `best_camera` (−1: camera 0), `scale` texels per camera pixel. Every corner's
/// UV is the centre of a texel that holds its vertex's colour (mesh.colors), so sampling the
/// atlas at any corner of a vertex, nearest or bilinear, gives the vertex's colour.
TexturedMesh bake_texture(const core::Mesh& mesh, const std::vector<render::Camera>& cameras,
                          const std::vector<render::Image>& images, const std::vector<int>& best_camera, double scale);

/// Writes `obj_path` (mtllib, usemtl, v, vt, f v/vt) with the MTL and PNG beside it, named after
/// its stem (atomic writes).
void write_textured_obj(const std::filesystem::path& obj_path, const TexturedMesh& textured);

}  // namespace surfcap::synth
