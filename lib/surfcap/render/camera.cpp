#include "surfcap/render/camera.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

#include "surfcap/core/error.hpp"

namespace surfcap::render {
namespace {

std::vector<double> row_major(const Eigen::Matrix3d& M) {
  std::vector<double> values;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) values.push_back(M(r, c));
  return values;
}

Eigen::Matrix3d matrix_field(const core::Json& entry, const char* key, const std::filesystem::path& source) {
  const auto values = core::get_field<std::vector<double>>(entry, key, source);
  if (values.size() != 9) throw core::bad_input(source, std::string("camera field \"") + key + "\" must hold 9 numbers");
  Eigen::Matrix3d M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M(r, c) = values[static_cast<std::size_t>(r * 3 + c)];
  return M;
}

}  // namespace

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

core::Json cameras_to_json(const std::vector<Camera>& cameras) {
  core::Json list = core::Json::array();
  for (const auto& camera : cameras)
    list.push_back({{"name", camera.name},
                    {"width", camera.width},
                    {"height", camera.height},
                    {"K", row_major(camera.K)},
                    {"dist", std::vector<double>(camera.dist.begin(), camera.dist.end())},
                    {"R", row_major(camera.R)},
                    {"t", std::vector<double>{camera.t.x(), camera.t.y(), camera.t.z()}}});
  return {{"format", core::format_tag("cameras", 1)}, {"cameras", list}};
}

std::vector<Camera> cameras_from_json(const core::Json& document, const std::filesystem::path& source) {
  const auto list = core::get_field<core::Json>(document, "cameras", source);
  if (!list.is_array() || list.empty()) throw core::bad_input(source, "\"cameras\" must be a non-empty array");
  std::vector<Camera> cameras;
  for (const auto& entry : list) {
    Camera camera;
    camera.name = core::get_field<std::string>(entry, "name", source);
    camera.width = core::get_field<int>(entry, "width", source);
    camera.height = core::get_field<int>(entry, "height", source);
    if (camera.width <= 0 || camera.height <= 0)
      throw core::bad_input(source, "camera '" + camera.name + "' has a non-positive image size");
    camera.K = matrix_field(entry, "K", source);
    camera.R = matrix_field(entry, "R", source);
    const auto t = core::get_field<std::vector<double>>(entry, "t", source);
    if (t.size() != 3) throw core::bad_input(source, "camera '" + camera.name + "': \"t\" must hold 3 numbers");
    camera.t = Eigen::Vector3d(t[0], t[1], t[2]);
    if (entry.contains("dist")) {
      const auto dist = core::get_field<std::vector<double>>(entry, "dist", source);
      if (dist.size() != 5) throw core::bad_input(source, "camera '" + camera.name + "': \"dist\" must hold 5 numbers");
      std::copy(dist.begin(), dist.end(), camera.dist.begin());
    }
    if ((camera.R * camera.R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 || camera.R.determinant() < 0)
      throw core::bad_input(source, "camera '" + camera.name + "': \"R\" is not a rotation");
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

void write_cameras(const std::filesystem::path& path, const std::vector<Camera>& cameras) {
  core::write_json_file(path, cameras_to_json(cameras));
}

std::vector<Camera> read_cameras(const std::filesystem::path& path) {
  return cameras_from_json(core::read_json_document(path, "cameras", 1), path);
}

}  // namespace surfcap::render
