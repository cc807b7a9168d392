#pragma once
// Shape from silhouette, the way many capture studios reconstruct: each camera's silhouette of
// the actor carves a voxel grid (a point is kept when every camera that frames it sees it inside
// the silhouette) and the carved volume's surface is extracted by marching tetrahedra.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "surfcap/core/mesh.hpp"
#include "surfcap/render/camera.hpp"

namespace surfcap::synth {

/// A camera's view of the actor: the pixels the actor covers (row-major, camera.width × height).
struct Silhouette {
  render::Camera camera;
  std::vector<std::uint8_t> mask;  ///< 1 inside the silhouette
};

/// The silhouette of `mesh` seen by `camera` (rasterised; a pixel is inside when its centre is).
Silhouette silhouette_of(const core::Mesh& mesh, const render::Camera& camera);
/// The same from a face buffer (render::Rendering::face, −1 where no surface).
Silhouette silhouette_from_faces(const render::Camera& camera, const std::vector<int>& faces);

/// A scalar field on a regular grid: value(i, j, k) at corner + voxel·(i, j, k); > 0 inside.
struct VoxelGrid {
  Eigen::Vector3d corner = Eigen::Vector3d::Zero();
  double voxel = 0.01;
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> value;  ///< x fastest, then y, then z
  float at(int i, int j, int k) const { return value[index(i, j, k)]; }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(ny) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(nx) + static_cast<std::size_t>(i);
  }
  Eigen::Vector3d point(int i, int j, int k) const { return corner + voxel * Eigen::Vector3d(i, j, k); }
};

/// The visual hull's signed distance (metres, approximately; > 0 inside) sampled on a grid of
/// `voxel` spacing covering [lower, upper] plus two voxels: the minimum over the cameras of the
/// distance to the silhouette's border (a pixel distance transform scaled by depth / focal
/// length). A camera that does not frame a point does not carve it; the grid's outer layer is
/// outside, so the surface is closed.
VoxelGrid carve_visual_hull(const std::vector<Silhouette>& silhouettes, const Eigen::Vector3d& lower,
                            const Eigen::Vector3d& upper, double voxel);

/// The zero level set of `grid` by marching tetrahedra (each cube split into six tetrahedra
/// along its main diagonal, which tiles space consistently): a closed, oriented (outward),
/// edge-manifold triangle mesh of as many components and handles as the carved volume has.
core::Mesh marching_tetrahedra(const VoxelGrid& grid);

}  // namespace surfcap::synth
