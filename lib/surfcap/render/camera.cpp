#include "surfcap/render/camera.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

#include "surfcap/core/error.hpp"

namespace surfcap::render {

Eigen::Vector2d Camera::project(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d p = K * to_camera(world);
  return p.head<2>() / p.z();
}

Camera look_at(const std::string& name, const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
               const Eigen::Vector3d& up, double vertical_fov_degrees, int width, int height) {
  Camera camera;
  camera.name = name;
  camera.width = width;
  camera.height = height;
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);  // points down in the image
  camera.R.row(0) = x.transpose();
  camera.R.row(1) = y.transpose();
  camera.R.row(2) = z.transpose();
  camera.t = -camera.R * eye;
  const double focal = 0.5 * height / std::tan(0.5 * vertical_fov_degrees * M_PI / 180.0);
  camera.K << focal, 0, 0.5 * (width - 1), 0, focal, 0.5 * (height - 1), 0, 0, 1;
  return camera;
}

std::vector<Camera> ring_cameras(int count, double radius, double height, const Eigen::Vector3d& target,
                                 double vertical_fov_degrees, int width, int height_pixels) {
  std::vector<Camera> cameras;
  for (int k = 0; k < count; ++k) {
    const double azimuth = 2 * M_PI * k / count;
    const Eigen::Vector3d eye(target.x() + radius * std::sin(azimuth), height, target.z() + radius * std::cos(azimuth));
    char name[16];
    std::snprintf(name, sizeof name, "cam%02d", k);
    cameras.push_back(look_at(name, eye, target, Eigen::Vector3d::UnitY(), vertical_fov_degrees, width, height_pixels));
  }
  return cameras;
}

core::CaptureCamera to_capture_camera(const Camera& camera) {
  core::CaptureCamera capture;
  capture.name = camera.name;
  capture.width = camera.width;
  capture.height = camera.height;
  capture.K = camera.K;
  capture.R = camera.R;
  capture.t = camera.t;
  for (int k = 0; k < 5; ++k) capture.distortion(k) = camera.dist[static_cast<std::size_t>(k)];
  return capture;
}

Camera from_capture_camera(const core::CaptureCamera& capture) {
  Camera camera;
  camera.name = capture.name;
  camera.width = capture.width;
  camera.height = capture.height;
  camera.K = capture.K;
  camera.R = capture.R;
  camera.t = capture.t;
  for (int k = 0; k < 5; ++k) camera.dist[static_cast<std::size_t>(k)] = capture.distortion(k);
  return camera;
}

void write_cameras(const std::filesystem::path& path, const std::vector<Camera>& cameras) {
  std::vector<core::CaptureCamera> converted;
  for (const auto& camera : cameras) converted.push_back(to_capture_camera(camera));
  core::write_cameras(path, converted);
}

std::vector<Camera> read_cameras(const std::filesystem::path& path) {
  std::vector<Camera> cameras;
  for (const auto& camera : core::read_cameras(path)) cameras.push_back(from_capture_camera(camera));
  return cameras;
}

}  // namespace surfcap::render
