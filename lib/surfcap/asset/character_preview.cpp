#include "surfcap/asset/character_preview.hpp"

#include <algorithm>

#include "surfcap/render/camera.hpp"
#include "surfcap/render/contact_sheet.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::asset {
namespace {

/// `mesh` seen from the front, framed by its bounding box.
render::Image front_view(const core::Mesh& mesh, const PreviewOptions& options) {
  const Eigen::Vector3d lo = mesh.V.colwise().minCoeff(), hi = mesh.V.colwise().maxCoeff();
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double fov = 30.0, half_height = 0.55 * std::max(hi.y() - lo.y(), (hi.x() - lo.x()) * options.cell_height /
                                                                              static_cast<double>(options.cell_width));
  const double distance = half_height / std::tan(fov * M_PI / 360.0) + 0.5 * (hi.z() - lo.z());
  const render::Camera camera = render::look_at("front", centre + Eigen::Vector3d(0, 0, distance), centre,
                                                Eigen::Vector3d::UnitY(), fov, options.cell_width, options.cell_height);
  render::RenderOptions render_options;
  render_options.background = Eigen::Vector3d(0.95, 0.95, 0.95);
  return render::render_mesh(mesh, camera, render_options).image;
}

}  // namespace

render::Image character_preview(const Character& character, const PreviewOptions& options) {
  std::vector<render::Image> cells{front_view(character.template_mesh, options)};
  render::ContactSheetOptions sheet;
  sheet.columns = options.columns;
  sheet.labels.push_back("template");
  core::Mesh posed = character.template_mesh;
  for (const core::AlignedSequence& sequence : character.sequences) {
    const int frames = sequence.frame_count(), shown = std::min(frames, options.frames_per_sequence);
    for (int k = 0; k < shown; ++k) {
      const int t = shown == 1 ? 0 : k * (frames - 1) / (shown - 1);
      posed.V = core::to_world(sequence.frames[t], sequence.root_motion[t]);
      cells.push_back(front_view(posed, options));
      sheet.labels.push_back(sequence.name + " " + std::to_string(t));
    }
  }
  return render::contact_sheet(cells, sheet);
}

}  // namespace surfcap::asset
