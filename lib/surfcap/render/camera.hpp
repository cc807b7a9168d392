#pragma once
// Pinhole cameras in OpenCV's convention (x right, y down, z forward; x_cam = R·X + t) and
// cameras.json (DESIGN §3.1), shared by the renderer, surfcap-synth and the aligner.

#include "surfcap/core/capture.hpp"
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/core/json_document.hpp"

namespace surfcap::render {

struct Camera {
  std::string name;
  int width = 640;
  int height = 480;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  ///< intrinsics, pixels; pixel centres at integers
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< world → camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      ///< world → camera translation (metres)
  std::array<double, 5> dist{};                     ///< OpenCV k1 k2 p1 p2 k3 (the renderer assumes zeros)

  Eigen::Vector3d to_camera(const Eigen::Vector3d& world) const { return R * world + t; }
  /// Pixel coordinates (x right, y down) of a world point; undefined behind the camera.
  Eigen::Vector2d project(const Eigen::Vector3d& world) const;
  /// Camera centre in world coordinates, −Rᵀt.
  Eigen::Vector3d centre() const { return -R.transpose() * t; }
  /// Viewing direction (+z of the camera) in world coordinates.
  Eigen::Vector3d forward() const { return R.row(2).transpose(); }
};

/// A camera at `eye` looking at `target`, `up` roughly up in the image, vertical field of view in
/// degrees, principal point at the image centre.
Camera look_at(const std::string& name, const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
               const Eigen::Vector3d& up, double vertical_fov_degrees, int width, int height);

/// `count` cameras evenly spaced on a horizontal circle (radius, height, centred on the vertical
/// axis through `target`), all looking at `target`; camera k at azimuth 2πk/count from +z, named
/// "cam00", "cam01"...
std::vector<Camera> ring_cameras(int count, double radius, double height, const Eigen::Vector3d& target,
                                 double vertical_fov_degrees, int width, int height_pixels);

/// The calibration as the capture folder stores it (core/capture owns the cameras.json format).
core::CaptureCamera to_capture_camera(const Camera& camera);
Camera from_capture_camera(const core::CaptureCamera& camera);
/// cameras.json through core::write_cameras / core::read_cameras (checked: bad_input names the file).
void write_cameras(const std::filesystem::path& path, const std::vector<Camera>& cameras);
std::vector<Camera> read_cameras(const std::filesystem::path& path);

}  // namespace surfcap::render
