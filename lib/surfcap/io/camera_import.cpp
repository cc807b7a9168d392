// What every calibration importer shares (camera_import.hpp).
#include "surfcap/io/camera_import.hpp"

#include <Eigen/LU>

#include <cmath>
#include <set>

#include "surfcap/core/error.hpp"

namespace surfcap::io {

void scale_translations(std::vector<core::CaptureCamera>& cameras, double scale) {
  if (!(scale > 0) || !std::isfinite(scale)) throw core::bad_arguments("--scale must be a positive number");
  for (auto& camera : cameras) camera.t *= scale;
}

void check_cameras(const std::vector<core::CaptureCamera>& cameras, const std::filesystem::path& source) {
  std::set<std::string> names;
  for (const auto& camera : cameras) {
    auto fail = [&](const std::string& what) { throw core::bad_input(source, "camera '" + camera.name + "': " + what); };
    if (camera.name.empty() || camera.name.find_first_of("/\\ {}") != std::string::npos || camera.name == "." ||
        camera.name == "..")
      fail("the name must be non-empty, without '/', '\\', spaces or braces (it names image folders)");
    if (!names.insert(camera.name).second) fail("appears twice");
    if (camera.width <= 0 || camera.height <= 0) fail("bad image size");
    if (!(camera.K(0, 0) > 0) || !(camera.K(1, 1) > 0)) fail("focal lengths must be positive");
    if (camera.K(1, 0) != 0 || camera.K(2, 0) != 0 || camera.K(2, 1) != 0 || camera.K(2, 2) != 1)
      fail("K must be [fx s cx; 0 fy cy; 0 0 1]");
    if (!camera.K.allFinite() || !camera.R.allFinite() || !camera.t.allFinite() || !camera.distortion.allFinite())
      fail("NaN/Inf in the calibration");
    if ((camera.R * camera.R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
        camera.R.determinant() < 0)
      fail("R is not a rotation");
  }
}

Eigen::Vector2d project(const core::CaptureCamera& camera, const Eigen::Vector3d& world) {
  const Eigen::Vector3d p = camera.R * world + camera.t;
  const double x = p.x() / p.z(), y = p.y() / p.z();
  const auto& d = camera.distortion;  // k1 k2 p1 p2 k3
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (d(0) + r2 * (d(1) + r2 * d(4)));
  const double xd = x * radial + 2 * d(2) * x * y + d(3) * (r2 + 2 * x * x);
  const double yd = y * radial + d(2) * (r2 + 2 * y * y) + 2 * d(3) * x * y;
  const Eigen::Vector3d pixel = camera.K * Eigen::Vector3d(xd, yd, 1.0);
  return pixel.head<2>();
}

}  // namespace surfcap::io
