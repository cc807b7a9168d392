#include "surfcap/runtime/play_preview.hpp"

#include <algorithm>

#include "surfcap/render/camera.hpp"
#include "surfcap/render/contact_sheet.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::runtime {

Eigen::Vector3d space_colour(int space, double parameter) {
  static const Eigen::Vector3d hues[] = {{0.20, 0.45, 0.90}, {0.95, 0.55, 0.15}, {0.25, 0.75, 0.35},
                                         {0.65, 0.35, 0.85}, {0.90, 0.30, 0.35}, {0.30, 0.75, 0.80}};
  const Eigen::Vector3d& hue = hues[space % 6];
  const double t = std::clamp(parameter, 0.0, 1.0);
  // Low parameter: the hue darkened; high: the hue lightened towards white.
  if (t < 0.5) return (0.45 + 1.1 * t) * hue;
  return hue + (t - 0.5) * 0.9 * (Eigen::Vector3d::Ones() - hue);
}

render::Image play_contact_sheet(const core::Mesh& template_mesh, const std::vector<PreviewFrame>& frames, int columns) {
  std::vector<render::Image> images;
  render::ContactSheetOptions sheet;
  sheet.columns = columns;
  const double height = template_mesh.V.col(1).maxCoeff() - template_mesh.V.col(1).minCoeff();
  for (const PreviewFrame& frame : frames) {
    core::Mesh mesh;
    mesh.V = frame.world;
    mesh.F = template_mesh.F;
    mesh.colors = space_colour(frame.space, frame.parameter).transpose().replicate(mesh.V.rows(), 1);
    const Eigen::Vector3d centre = 0.5 * (mesh.V.colwise().minCoeff() + mesh.V.colwise().maxCoeff()).transpose();
    // A three-quarter view from a fixed world direction, far enough to hold a standing figure.
    const Eigen::Vector3d eye = centre + height * Eigen::Vector3d(1.6, 0.35, 1.6);
    const render::Camera camera = render::look_at("preview", eye, centre, {0, 1, 0}, 40.0, 160, 220);
    render::RenderOptions options;
    options.background = {0.95, 0.95, 0.95};
    images.push_back(render::render_mesh(mesh, camera, options).image);
    sheet.labels.push_back(frame.label);
  }
  return render::contact_sheet(images, sheet);
}

}  // namespace surfcap::runtime
