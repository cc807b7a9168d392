// COLMAP text model → capture cameras (camera_import.hpp).
#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <sstream>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/io/camera_import.hpp"

namespace surfcap::io {
namespace {

struct ColmapCamera {
  int width = 0, height = 0;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 5, 1> distortion = Eigen::Matrix<double, 5, 1>::Zero();
};

/// Lines of a COLMAP text file, without comments and surrounding blanks, with their numbers.
/// Empty lines are kept: images.txt's second line of an image may be empty.
std::vector<std::pair<long, std::string>> lines_of(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw core::bad_input(file, "missing (a COLMAP text model needs cameras.txt and images.txt)");
  std::istringstream in(core::read_file(file));
  std::vector<std::pair<long, std::string>> lines;
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    const auto begin = line.find_first_not_of(" \t\r");
    const auto end = line.find_last_not_of(" \t\r");
    line = begin == std::string::npos ? std::string() : line.substr(begin, end - begin + 1);
    if (!line.empty() && line[0] == '#') continue;
    lines.emplace_back(number, line);
  }
  return lines;
}

/// Whitespace-separated numbers of `text`; bad_input at `file`:`line` if one is not a finite number.
std::vector<double> numbers(const std::string& text, const std::filesystem::path& file, long line) {
  std::istringstream words(text);
  std::vector<double> values;
  for (std::string word; words >> word;) {
    char* end = nullptr;
    const double value = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0' || !std::isfinite(value))
      throw core::bad_input(file, "line " + std::to_string(line) + ": '" + word + "' is not a finite number");
    values.push_back(value);
  }
  return values;
}

ColmapCamera colmap_camera(const std::string& model, const std::vector<double>& p, const std::filesystem::path& file,
                           long line) {
  static const std::map<std::string, std::size_t> parameters = {{"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4},
                                                                {"SIMPLE_RADIAL", 4}, {"RADIAL", 5},
                                                                {"OPENCV", 8}, {"FULL_OPENCV", 12}};
  const auto it = parameters.find(model);
  if (it == parameters.end())
    throw core::bad_input(file, "line " + std::to_string(line) + ": camera model " + model +
                                    " is not supported (SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, "
                                    "FULL_OPENCV without k4..k6)");
  if (p.size() != it->second)
    throw core::bad_input(file, "line " + std::to_string(line) + ": " + model + " takes " + std::to_string(it->second) +
                                    " parameters, the line has " + std::to_string(p.size()));
  ColmapCamera camera;
  const bool one_focal = model == "SIMPLE_PINHOLE" || model == "SIMPLE_RADIAL" || model == "RADIAL";
  const double fx = p[0], fy = one_focal ? p[0] : p[1];
  const std::size_t c = one_focal ? 1 : 2;
  // COLMAP: the top-left pixel's centre is at (0.5, 0.5); OpenCV and surfcap: at (0, 0).
  camera.K << fx, 0, p[c] - 0.5, 0, fy, p[c + 1] - 0.5, 0, 0, 1;
  if (model == "SIMPLE_RADIAL") camera.distortion(0) = p[3];
  if (model == "RADIAL") camera.distortion.head<2>() << p[3], p[4];
  if (model == "OPENCV" || model == "FULL_OPENCV") camera.distortion.head<4>() << p[4], p[5], p[6], p[7];
  if (model == "FULL_OPENCV") {
    if (p[9] != 0 || p[10] != 0 || p[11] != 0)
      throw core::bad_input(file, "line " + std::to_string(line) +
                                      ": FULL_OPENCV with rational coefficients k4..k6 is not supported (cameras.json "
                                      "holds k1 k2 p1 p2 k3)");
    camera.distortion(4) = p[8];
  }
  return camera;
}

std::map<long, ColmapCamera> read_colmap_intrinsics(const std::filesystem::path& file) {
  std::map<long, ColmapCamera> cameras;
  for (const auto& [number, line] : lines_of(file)) {
    if (line.empty()) continue;
    std::istringstream words(line);
    long id = 0;
    std::string model;
    double width = 0, height = 0;
    if (!(words >> id >> model >> width >> height) || width < 1 || height < 1 || width > 1e6 || height > 1e6 ||
        width != std::floor(width) || height != std::floor(height))
      throw core::bad_input(file, "line " + std::to_string(number) + ": expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    std::string rest;
    std::getline(words, rest);
    ColmapCamera camera = colmap_camera(model, numbers(rest, file, number), file, number);
    camera.width = static_cast<int>(width);
    camera.height = static_cast<int>(height);
    if (!cameras.emplace(id, camera).second)
      throw core::bad_input(file, "line " + std::to_string(number) + ": camera " + std::to_string(id) + " appears twice");
  }
  if (cameras.empty()) throw core::bad_input(file, "no cameras");
  return cameras;
}

/// "cam03/000000.png" → cam03; "cam03.png" → cam03.
std::string camera_name(const std::string& image) {
  const std::filesystem::path path(image);
  return path.has_parent_path() ? path.parent_path().filename().string() : path.stem().string();
}

}  // namespace

std::vector<core::CaptureCamera> read_colmap_cameras(const std::filesystem::path& folder) {
  const auto cameras_txt = folder / "cameras.txt", images_txt = folder / "images.txt";
  const std::map<long, ColmapCamera> intrinsics = read_colmap_intrinsics(cameras_txt);
  const auto lines = lines_of(images_txt);
  std::vector<core::CaptureCamera> cameras;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const auto& [number, line] = lines[i];
    if (line.empty()) continue;
    std::istringstream words(line);
    long id = 0, camera_id = 0;
    double q[4], t[3];
    std::string name;
    if (!(words >> id >> q[0] >> q[1] >> q[2] >> q[3] >> t[0] >> t[1] >> t[2] >> camera_id >> name))
      throw core::bad_input(images_txt, "line " + std::to_string(number) +
                                            ": expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    ++i;  // the image's POINTS2D line (possibly empty)
    const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
    if (!std::isfinite(rotation.norm()) || std::abs(rotation.norm() - 1) > 1e-3 || !Eigen::Vector3d(t[0], t[1], t[2]).allFinite())
      throw core::bad_input(images_txt, "line " + std::to_string(number) + ": the pose needs a unit quaternion and a finite translation");
    const auto found = intrinsics.find(camera_id);
    if (found == intrinsics.end())
      throw core::bad_input(images_txt, "line " + std::to_string(number) + ": camera " + std::to_string(camera_id) +
                                            " is not in cameras.txt");
    core::CaptureCamera camera;
    camera.name = camera_name(name);
    camera.width = found->second.width;
    camera.height = found->second.height;
    camera.K = found->second.K;
    camera.distortion = found->second.distortion;
    camera.R = rotation.normalized().toRotationMatrix();
    camera.t << t[0], t[1], t[2];
    for (const auto& other : cameras)
      if (other.name == camera.name)
        throw core::bad_input(images_txt, "line " + std::to_string(number) + ": a second image of camera '" + camera.name +
                                              "' (one image per camera: a rig's calibration frame)");
    cameras.push_back(camera);
  }
  if (cameras.empty()) throw core::bad_input(images_txt, "no images");
  check_cameras(cameras, images_txt);
  return cameras;
}

}  // namespace surfcap::io
