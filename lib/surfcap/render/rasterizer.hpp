#pragma once
// A small software rasteriser (z-buffer, perspective-correct interpolation, Lambert + ambient
// lighting): synthetic camera images and PNG previews without a GPU or OpenGL.

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "surfcap/core/mesh.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/render/image.hpp"

namespace surfcap::render {

/// Albedo (0..1) at a surface point given by face and barycentric coordinates (summing to 1).
using SurfaceColor = std::function<Eigen::Vector3d(long face, const Eigen::Vector3d& barycentric)>;

struct RenderOptions {
  Eigen::Vector3d background{1.0, 1.0, 1.0};
  /// Albedo where neither surface_color nor per-vertex colours are given.
  Eigen::Vector3d default_color{0.75, 0.75, 0.75};
  /// Per-pixel albedo (e.g. a procedural texture); else interpolated vertex colours.
  SurfaceColor surface_color;
  double ambient = 0.35;
  double diffuse = 0.65;
  /// Direction towards the light in world coordinates; zero: a headlight from the camera.
  Eigen::Vector3d light_direction = Eigen::Vector3d::Zero();
  bool smooth_normals = true;  ///< interpolated vertex normals (else flat face normals)
};

/// What one render produces; buffers are width×height, row-major.
struct Rendering {
  Image image;
  std::vector<float> depth;      ///< camera z (metres) of the visible surface, +inf where none
  std::vector<int> face;         ///< visible face index, −1 where none
  /// Shaded colour of a surface point seen with normal `normal` (unit, world) from `camera`.
  Eigen::Vector3d shade(const Eigen::Vector3d& albedo, const Eigen::Vector3d& normal, const Camera& camera) const;
  RenderOptions options;
};

/// What a camera sees of a surface, without shading: buffers are width×height, row-major.
struct Visibility {
  std::vector<float> depth;  ///< camera z (metres) of the visible surface, +inf where none
  std::vector<int> face;     ///< visible face index, −1 where none
};

/// The visible face and depth per pixel of (V, F) seen by `camera` (pixel centres at integer
/// coordinates); faces with a vertex behind the near plane are skipped. render_mesh's buffers.
Visibility render_visibility(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Camera& camera,
                             double near = 0.05);

/// Renders `mesh` as seen by `camera` (its width × height). Faces behind the near plane
/// (z < near) are skipped; both sides of a face are lit (the normal facing the camera is used).
Rendering render_mesh(const core::Mesh& mesh, const Camera& camera, const RenderOptions& options = {},
                      double near = 0.05);

}  // namespace surfcap::render
