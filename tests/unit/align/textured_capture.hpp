#pragma once
// A small multi-view "capture" of the test body (deformable_shape.hpp) with a high-contrast solid
// texture fixed to its rest position, rendered by the software rasteriser into a temporary capture
// folder: two frames, rest and bent + twisted, for image-feature tests and benchmarks.

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "deformable_shape.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::align::testing {

/// Blobs on a 4 cm grid of the rest position, two contrasting colours on a mid background.
inline Eigen::Vector3d blob_pattern(const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = p / 0.04;
  const Eigen::Vector3d cell = q.array().floor();
  const double hash = std::sin(cell.dot(Eigen::Vector3d(12.9898, 78.233, 37.719))) * 43758.5453;
  const double u = hash - std::floor(hash);
  const double r = (q - cell - Eigen::Vector3d::Constant(0.5)).norm();
  if (r < 0.25 + 0.15 * u) return u < 0.5 ? Eigen::Vector3d(0.1, 0.1, 0.15) : Eigen::Vector3d(0.95, 0.9, 0.3);
  return {0.55 + 0.3 * u, 0.35, 0.3};
}

struct TexturedCapture {
  core::Capture capture;
  core::Mesh rest;
  std::vector<Eigen::MatrixXd> frames;  ///< true vertex positions per frame

  TexturedCapture(const std::string& tag, int cameras, int size) {
    capture.folder = std::filesystem::temp_directory_path() / ("surfcap_" + tag + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(capture.folder);
    const auto rig = render::ring_cameras(cameras, 2.5, 0.2, Eigen::Vector3d::Zero(), 45, size, size);
    for (const auto& camera : rig) capture.cameras.push_back(render::to_capture_camera(camera));
    capture.sequences.push_back({"s", "s/mesh/{frame:06d}.ply", "s/images/{camera}/{frame:06d}.png", 0, 2});
    rest = ellipsoid(40, 80);
    frames = {rest.V, deform_points(rest.V, 0.25, 0.15, {0.03, 0.01, -0.02})};
    render::RenderOptions options;
    options.surface_color = [this](long face, const Eigen::Vector3d& b) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) p += b(k) * rest.V.row(rest.F(face, k)).transpose();
      return blob_pattern(p);
    };
    for (int frame = 0; frame < 2; ++frame) {
      core::Mesh mesh = rest;
      mesh.V = frames[static_cast<std::size_t>(frame)];
      for (std::size_t c = 0; c < rig.size(); ++c) {
        const auto path = capture.image_path(0, frame, static_cast<int>(c));
        std::filesystem::create_directories(path.parent_path());
        render::write_png(path, render::render_mesh(mesh, rig[c], options).image);
      }
    }
  }
  ~TexturedCapture() { std::filesystem::remove_all(capture.folder); }
  TexturedCapture(const TexturedCapture&) = delete;
  TexturedCapture& operator=(const TexturedCapture&) = delete;
};

}  // namespace surfcap::align::testing
