#include "surfcap/render/rasterizer.hpp"

#include <algorithm>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <limits>

namespace surfcap::render {
namespace {

struct ScreenVertex {
  double x, y, inverse_depth;
};

/// Twice the signed area of (a, b, p) in screen space.
double edge(const ScreenVertex& a, const ScreenVertex& b, double px, double py) {
  return (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
}

struct Buffers {
  int width, height;
  std::vector<float>& depth;
  std::vector<int>& face;
  std::vector<Eigen::Vector3f>* barycentric;  ///< null: not wanted
};

void rasterize_face(long f, const ScreenVertex (&s)[3], Buffers& buffers) {
  const double area = edge(s[0], s[1], s[2].x, s[2].y);
  if (std::abs(area) < 1e-12) return;
  const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({s[0].x, s[1].x, s[2].x}))));
  const int x1 = std::min(buffers.width - 1, static_cast<int>(std::floor(std::max({s[0].x, s[1].x, s[2].x}))));
  const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({s[0].y, s[1].y, s[2].y}))));
  const int y1 = std::min(buffers.height - 1, static_cast<int>(std::floor(std::max({s[0].y, s[1].y, s[2].y}))));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      // Screen-space barycentrics; the same sign as the area means inside (either winding). The
      // signs of the first two are those of their edge functions: tested before dividing.
      const double e0 = edge(s[1], s[2], x, y), e1 = edge(s[2], s[0], x, y);
      if ((area > 0) ? (e0 < 0 || e1 < 0) : (e0 > 0 || e1 > 0)) continue;
      const double l0 = e0 / area, l1 = e1 / area;
      const double l2 = 1.0 - l0 - l1;
      if (l0 < 0 || l1 < 0 || l2 < 0) continue;
      // Perspective-correct: 1/z is affine in screen space.
      const double inverse_depth = l0 * s[0].inverse_depth + l1 * s[1].inverse_depth + l2 * s[2].inverse_depth;
      const double depth = 1.0 / inverse_depth;
      const std::size_t pixel = static_cast<std::size_t>(y) * buffers.width + x;
      if (depth >= buffers.depth[pixel]) continue;
      buffers.depth[pixel] = static_cast<float>(depth);
      buffers.face[pixel] = static_cast<int>(f);
      if (buffers.barycentric == nullptr) continue;
      const Eigen::Vector3d b = Eigen::Vector3d(l0 * s[0].inverse_depth, l1 * s[1].inverse_depth,
                                                l2 * s[2].inverse_depth) * depth;
      (*buffers.barycentric)[pixel] = b.cast<float>();
    }
}

/// Rasterises the faces of (V, F) seen by `camera` into `buffers` (depth +inf, face −1 to start).
void rasterize(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Camera& camera, double near,
               Buffers& buffers) {
  const long n = V.rows();
  std::vector<ScreenVertex> screen(static_cast<std::size_t>(n));
  std::vector<bool> in_front(static_cast<std::size_t>(n));
  for (long v = 0; v < n; ++v) {
    const Eigen::Vector3d c = camera.to_camera(V.row(v).transpose());
    const Eigen::Vector3d p = camera.K * c;
    in_front[v] = c.z() > near;
    screen[v] = {p.x() / p.z(), p.y() / p.z(), 1.0 / c.z()};
  }
  for (long f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (!in_front[a] || !in_front[b] || !in_front[c]) continue;
    const ScreenVertex s[3] = {screen[a], screen[b], screen[c]};
    rasterize_face(f, s, buffers);
  }
}

}  // namespace

Visibility render_visibility(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Camera& camera, double near) {
  Visibility result;
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
  result.depth.assign(pixels, std::numeric_limits<float>::infinity());
  result.face.assign(pixels, -1);
  Buffers buffers{camera.width, camera.height, result.depth, result.face, nullptr};
  rasterize(V, F, camera, near, buffers);
  return result;
}

Eigen::Vector3d Rendering::shade(const Eigen::Vector3d& albedo, const Eigen::Vector3d& normal,
                                 const Camera& camera) const {
  const Eigen::Vector3d light = options.light_direction.isZero() ? Eigen::Vector3d(-camera.forward())
                                                                  : options.light_direction.normalized();
  Eigen::Vector3d n = normal;
  if (n.dot(camera.forward()) > 0) n = -n;  // the side facing the camera
  const double lambert = std::max(0.0, n.dot(light));
  return albedo * (options.ambient + options.diffuse * lambert);
}

Rendering render_mesh(const core::Mesh& mesh, const Camera& camera, const RenderOptions& options, double near) {
  Rendering result;
  result.options = options;
  const int width = camera.width, height = camera.height;
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  result.image = Image(width, height, options.background);
  result.depth.assign(pixels, std::numeric_limits<float>::infinity());
  result.face.assign(pixels, -1);
  std::vector<Eigen::Vector3f> barycentric(pixels);
  Buffers buffers{width, height, result.depth, result.face, &barycentric};
  rasterize(mesh.V, mesh.F, camera, near, buffers);

  Eigen::MatrixXd normals;
  if (options.smooth_normals) normals = core::vertex_normals(mesh.V, mesh.F);
  for (std::size_t pixel = 0; pixel < pixels; ++pixel) {
    const int f = result.face[pixel];
    if (f < 0) continue;
    const Eigen::Vector3d b = barycentric[pixel].cast<double>();
    const int i0 = mesh.F(f, 0), i1 = mesh.F(f, 1), i2 = mesh.F(f, 2);
    Eigen::Vector3d normal;
    if (options.smooth_normals) {
      normal = (b[0] * normals.row(i0) + b[1] * normals.row(i1) + b[2] * normals.row(i2)).transpose();
    } else {
      const Eigen::Vector3d e1 = (mesh.V.row(i1) - mesh.V.row(i0)).transpose();
      const Eigen::Vector3d e2 = (mesh.V.row(i2) - mesh.V.row(i0)).transpose();
      normal = e1.cross(e2);
    }
    if (normal.norm() > 0) normal.normalize();
    Eigen::Vector3d albedo = options.default_color;
    if (options.surface_color) {
      albedo = options.surface_color(f, b);
    } else if (mesh.has_colors()) {
      albedo = (b[0] * mesh.colors.row(i0) + b[1] * mesh.colors.row(i1) + b[2] * mesh.colors.row(i2)).transpose();
    }
    const int x = static_cast<int>(pixel % width), y = static_cast<int>(pixel / width);
    result.image.set(x, y, result.shade(albedo, normal, camera));
  }
  return result;
}

}  // namespace surfcap::render
