#include "surfcap/synth/visual_hull.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

#include "surfcap/core/error.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::synth {
namespace {

/// Signed distance to the silhouette's border in pixels (> 0 inside), per
/// pixel.
cv::Mat signed_distance(const Silhouette& silhouette) {
  const int width = silhouette.camera.width, height = silhouette.camera.height;
  cv::Mat inside(height, width, CV_8U), outside(height, width, CV_8U);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const bool in =
          silhouette
              .mask[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] != 0;
      inside.at<std::uint8_t>(y, x) = in ? 255 : 0;
      outside.at<std::uint8_t>(y, x) = in ? 0 : 255;
    }
  cv::Mat distance_in, distance_out;
  cv::distanceTransform(inside, distance_in, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::distanceTransform(outside, distance_out, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  // The border lies half a pixel beyond the last pixel centre inside.
  cv::Mat result(height, width, CV_32F);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float in = distance_in.at<float>(y, x), out = distance_out.at<float>(y, x);
      result.at<float>(y, x) = in > 0 ? in - 0.5f : -(out - 0.5f);
    }
  return result;
}

double bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, image.cols - 2);
  const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, image.rows - 2);
  const double fx = std::clamp(x - x0, 0.0, 1.0), fy = std::clamp(y - y0, 0.0, 1.0);
  return (1 - fy) * ((1 - fx) * image.at<float>(y0, x0) + fx * image.at<float>(y0, x0 + 1)) +
         fy * ((1 - fx) * image.at<float>(y0 + 1, x0) + fx * image.at<float>(y0 + 1, x0 + 1));
}

/// The zero level set of a voxel grid's field, built one tetrahedron at a time; a vertex on each
/// grid edge the surface crosses, shared by the triangles of every tetrahedron around that edge.
class TetrahedraSurface {
 public:
  explicit TetrahedraSurface(const VoxelGrid& grid)
      : grid_(grid), total_(static_cast<std::uint64_t>(grid.value.size())) {}

  bool inside(std::size_t g) const { return grid_.value[g] > 0; }

  /// The triangles of one tetrahedron (grid point indices), oriented from its inside points to
  /// its outside ones.
  void add_tetrahedron(const std::array<std::size_t, 4>& points) {
    std::array<std::size_t, 4> in_points, out_points;
    int n_in = 0, n_out = 0;
    for (std::size_t g : points) {
      if (inside(g))
        in_points[n_in++] = g;
      else
        out_points[n_out++] = g;
    }
    if (n_in == 0 || n_out == 0) return;
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    for (int o = 0; o < n_out; ++o) outward += position(out_points[o]) / n_out;
    for (int o = 0; o < n_in; ++o) outward -= position(in_points[o]) / n_in;
    if (n_in == 1) {
      emit(crossing(in_points[0], out_points[0]), crossing(in_points[0], out_points[1]),
           crossing(in_points[0], out_points[2]), outward);
    } else if (n_in == 3) {
      emit(crossing(in_points[0], out_points[0]), crossing(in_points[1], out_points[0]),
           crossing(in_points[2], out_points[0]), outward);
    } else {
      const int q0 = crossing(in_points[0], out_points[0]), q1 = crossing(in_points[0], out_points[1]);
      const int q2 = crossing(in_points[1], out_points[1]), q3 = crossing(in_points[1], out_points[0]);
      emit(q0, q1, q2, outward);
      emit(q0, q2, q3, outward);
    }
  }

  core::Mesh mesh() const {
    core::Mesh mesh;
    mesh.V.resize(static_cast<long>(vertices_.size()), 3);
    for (std::size_t v = 0; v < vertices_.size(); ++v) mesh.V.row(static_cast<long>(v)) = vertices_[v].transpose();
    mesh.F.resize(static_cast<long>(faces_.size()), 3);
    for (std::size_t f = 0; f < faces_.size(); ++f) mesh.F.row(static_cast<long>(f)) = faces_[f].transpose();
    return mesh;
  }

 private:
  Eigen::Vector3d position(std::size_t g) const {
    const std::size_t i = g % static_cast<std::size_t>(grid_.nx);
    const std::size_t j = g / static_cast<std::size_t>(grid_.nx) % static_cast<std::size_t>(grid_.ny);
    const std::size_t k = g / (static_cast<std::size_t>(grid_.nx) * static_cast<std::size_t>(grid_.ny));
    return grid_.point(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
  }

  /// The vertex where the field crosses zero on the edge from an inside to an outside grid point.
  int crossing(std::size_t in, std::size_t out) {
    const std::uint64_t key = std::min<std::uint64_t>(in, out) * total_ + std::max<std::uint64_t>(in, out);
    const auto found = edge_vertex_.find(key);
    if (found != edge_vertex_.end()) return found->second;
    const double a = grid_.value[in], b = grid_.value[out];
    // Kept off the grid points, so no triangle degenerates to a point.
    const double t = std::clamp(a / (a - b), 0.01, 0.99);
    vertices_.push_back((1 - t) * position(in) + t * position(out));
    const int index = static_cast<int>(vertices_.size()) - 1;
    edge_vertex_.emplace(key, index);
    return index;
  }

  void emit(int a, int b, int c, const Eigen::Vector3d& outward) {
    const Eigen::Vector3d normal = (vertices_[b] - vertices_[a]).cross(vertices_[c] - vertices_[a]);
    faces_.push_back(normal.dot(outward) >= 0 ? Eigen::Vector3i(a, b, c) : Eigen::Vector3i(a, c, b));
  }

  const VoxelGrid& grid_;
  const std::uint64_t total_;
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Eigen::Vector3i> faces_;
  std::unordered_map<std::uint64_t, int> edge_vertex_;
};

}  // namespace

Silhouette silhouette_from_faces(const render::Camera& camera, const std::vector<int>& faces) {
  Silhouette result;
  result.camera = camera;
  result.mask.resize(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) result.mask[i] = faces[i] >= 0 ? 1 : 0;
  return result;
}

Silhouette silhouette_of(const core::Mesh& mesh, const render::Camera& camera) {
  return silhouette_from_faces(camera, render::render_mesh(mesh, camera).face);
}

VoxelGrid carve_visual_hull(const std::vector<Silhouette>& silhouettes, const Eigen::Vector3d& lower,
                            const Eigen::Vector3d& upper, double voxel) {
  if (!(voxel > 0)) throw core::internal_error("carve_visual_hull: the voxel size must be positive");
  VoxelGrid grid;
  grid.voxel = voxel;
  grid.corner = lower - Eigen::Vector3d::Constant(2 * voxel);
  const Eigen::Vector3d extent = upper - lower + Eigen::Vector3d::Constant(4 * voxel);
  grid.nx = static_cast<int>(std::ceil(extent.x() / voxel)) + 1;
  grid.ny = static_cast<int>(std::ceil(extent.y() / voxel)) + 1;
  grid.nz = static_cast<int>(std::ceil(extent.z() / voxel)) + 1;
  const double cells = static_cast<double>(grid.nx) * grid.ny * grid.nz;
  if (cells > 4e8)
    throw core::internal_error("carve_visual_hull: the grid would hold " + std::to_string(cells) + " voxels");
  // Far from the border only the sign matters: values are clamped to ±3 voxels.
  const float limit = static_cast<float>(3 * voxel);
  grid.value.assign(static_cast<std::size_t>(cells), limit);
  for (const auto& silhouette : silhouettes) {
    const render::Camera& camera = silhouette.camera;
    if (silhouette.mask.size() != static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height))
      throw core::internal_error("carve_visual_hull: a silhouette's size differs from its camera's");
    const cv::Mat distance = signed_distance(silhouette);
    const double focal = camera.K(1, 1);
    for (int k = 0; k < grid.nz; ++k)
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) {
          float& value = grid.value[grid.index(i, j, k)];
          if (value <= -limit) continue;
          const Eigen::Vector3d c = camera.to_camera(grid.point(i, j, k));
          if (c.z() <= 1e-6) continue;
          const Eigen::Vector3d p = camera.K * c;
          const double x = p.x() / p.z(), y = p.y() / p.z();
          if (x < -0.5 || y < -0.5 || x > camera.width - 0.5 || y > camera.height - 0.5) continue;  // not framed
          const double metres = bilinear(distance, x, y) * c.z() / focal;
          value = std::min(value, static_cast<float>(std::max<double>(metres, -limit)));
        }
  }
  // The outer layer is outside: the extracted surface is closed.
  for (int k = 0; k < grid.nz; ++k)
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        if (i == 0 || j == 0 || k == 0 || i == grid.nx - 1 || j == grid.ny - 1 || k == grid.nz - 1)
          grid.value[grid.index(i, j, k)] = -limit;
  return grid;
}

core::Mesh marching_tetrahedra(const VoxelGrid& grid) {
  // Cube corner c is at offset (c & 1, c >> 1 & 1, c >> 2 & 1); the six
  // tetrahedra of the cube are the monotone paths 0 → a → a+b → 7 over the
  // orderings of the axes (Kuhn's triangulation: neighbouring cubes split their
  // shared face along the same diagonal).
  static constexpr std::array<std::array<int, 4>, 6> tetrahedra = {
      {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};
  TetrahedraSurface surface(grid);
  for (int k = 0; k + 1 < grid.nz; ++k)
    for (int j = 0; j + 1 < grid.ny; ++j)
      for (int i = 0; i + 1 < grid.nx; ++i) {
        std::array<std::size_t, 8> corner;
        int count_inside = 0;
        for (int c = 0; c < 8; ++c) {
          corner[c] = grid.index(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
          count_inside += surface.inside(corner[c]);
        }
        if (count_inside == 0 || count_inside == 8) continue;
        for (const auto& tetrahedron : tetrahedra)
          surface.add_tetrahedron({corner[static_cast<std::size_t>(tetrahedron[0])],
                                   corner[static_cast<std::size_t>(tetrahedron[1])],
                                   corner[static_cast<std::size_t>(tetrahedron[2])],
                                   corner[static_cast<std::size_t>(tetrahedron[3])]});
      }
  return surface.mesh();
}

}  // namespace surfcap::synth
