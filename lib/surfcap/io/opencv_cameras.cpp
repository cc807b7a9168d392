// OpenCV FileStorage calibrations (YAML/XML) → capture cameras (camera_import.hpp).
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <cmath>
#include <initializer_list>

#include "surfcap/core/error.hpp"
#include "surfcap/io/camera_import.hpp"

namespace surfcap::io {
namespace {

/// The first of `keys` present in `node` (empty node if none).
cv::FileNode field(const cv::FileNode& node, std::initializer_list<const char*> keys) {
  for (const char* key : keys) {
    const cv::FileNode found = node[key];
    if (!found.empty() && !found.isNone()) return found;
  }
  return {};
}

bool has_intrinsics(const cv::FileNode& node) {
  return node.isMap() && !field(node, {"K", "camera_matrix", "cameraMatrix"}).empty();
}

/// A matrix node (opencv-matrix) or a plain sequence of numbers, as doubles in row-major order.
std::vector<double> values(const cv::FileNode& node) {
  std::vector<double> out;
  if (node.isSeq()) {
    for (const auto& item : node) {
      if (!item.isReal() && !item.isInt()) return {};
      out.push_back(static_cast<double>(item));
    }
    return out;
  }
  cv::Mat matrix;
  node >> matrix;
  if (matrix.empty()) return {};
  matrix.convertTo(matrix, CV_64F);
  matrix = matrix.reshape(1, 1);
  return std::vector<double>(matrix.begin<double>(), matrix.end<double>());
}

class CameraReader {
 public:
  CameraReader(const std::filesystem::path& file, std::string name) : file_(file), name_(std::move(name)) {}

  core::CaptureCamera read(const cv::FileNode& node) const {
    core::CaptureCamera camera;
    camera.name = name_;
    const auto K = numbers(node, {"K", "camera_matrix", "cameraMatrix"}, "K", {9});
    camera.K = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(K.data());
    const cv::FileNode dist = field(node, {"dist", "distortion_coefficients", "dist_coeffs", "distCoeffs", "D"});
    if (!dist.empty()) {
      const auto d = numbers(node, {"dist", "distortion_coefficients", "dist_coeffs", "distCoeffs", "D"}, "dist",
                             {4, 5, 8, 12, 14});
      for (std::size_t k = 0; k < d.size(); ++k) {
        if (k < 5) camera.distortion(static_cast<long>(k)) = d[k];
        else if (d[k] != 0) fail("distortion coefficients after k3 (rational, thin-prism, tilt) are not supported");
      }
    }
    const auto R = numbers(node, {"R", "rotation", "rvec"}, "R", {9, 3});
    if (R.size() == 9) {
      camera.R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R.data());
    } else {
      cv::Mat rotation;
      cv::Rodrigues(cv::Mat(R, true), rotation);  // a rotation vector (axis × angle)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) camera.R(r, c) = rotation.at<double>(r, c);
    }
    const auto t = numbers(node, {"t", "T", "tvec", "translation"}, "t", {3});
    camera.t << t[0], t[1], t[2];
    read_size(node, camera);
    return camera;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw core::bad_input(file_, "camera '" + name_ + "': " + what);
  }

  std::vector<double> numbers(const cv::FileNode& node, std::initializer_list<const char*> keys, const std::string& what,
                              std::initializer_list<std::size_t> sizes) const {
    const cv::FileNode found = field(node, keys);
    if (found.empty()) fail("no " + what + " (" + *keys.begin() + ")");
    const std::vector<double> out = values(found);
    if (std::find(sizes.begin(), sizes.end(), out.size()) == sizes.end())
      fail(what + " has " + std::to_string(out.size()) + " numbers");
    for (const double value : out)
      if (!std::isfinite(value)) fail(what + " has NaN/Inf");
    return out;
  }

  void read_size(const cv::FileNode& node, core::CaptureCamera& camera) const {
    const cv::FileNode size = field(node, {"image_size", "imageSize"});
    std::vector<double> wh;
    if (!size.empty()) {
      wh = values(size);
    } else {
      const cv::FileNode width = field(node, {"width", "image_width"}), height = field(node, {"height", "image_height"});
      if (width.empty() || height.empty()) fail("no image size (width and height, or image_size)");
      wh = {static_cast<double>(width), static_cast<double>(height)};
    }
    if (wh.size() != 2 || !(wh[0] >= 1 && wh[0] <= 1e6 && wh[1] >= 1 && wh[1] <= 1e6) || wh[0] != std::floor(wh[0]) ||
        wh[1] != std::floor(wh[1]))
      fail("bad image size");
    camera.width = static_cast<int>(wh[0]);
    camera.height = static_cast<int>(wh[1]);
  }

  std::filesystem::path file_;
  std::string name_;
};

}  // namespace

std::vector<core::CaptureCamera> read_opencv_cameras(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw core::io_error(file, "no such file");
  std::vector<core::CaptureCamera> cameras;
  try {
    cv::FileStorage storage(file.string(), cv::FileStorage::READ);
    if (!storage.isOpened()) throw core::bad_input(file, "not an OpenCV FileStorage file (YAML or XML)");
    const cv::FileNode root = storage.root();
    if (has_intrinsics(root)) {
      const cv::FileNode name = root["name"];
      cameras.push_back(CameraReader(file, name.isString() ? name.string() : file.stem().string()).read(root));
    } else if (const cv::FileNode list = root["cameras"]; list.isSeq()) {
      for (const auto& entry : list) {
        const cv::FileNode name = entry["name"];
        if (!name.isString()) throw core::bad_input(file, "every entry of \"cameras\" needs a \"name\"");
        cameras.push_back(CameraReader(file, name.string()).read(entry));
      }
    } else {
      for (const auto& entry : root)
        if (has_intrinsics(entry)) cameras.push_back(CameraReader(file, entry.name()).read(entry));
    }
  } catch (const cv::Exception& e) {
    throw core::bad_input(file, std::string("could not be read as OpenCV FileStorage: ") + e.msg);
  }
  if (cameras.empty()) throw core::bad_input(file, "no camera (a map with K or camera_matrix)");
  check_cameras(cameras, file);
  return cameras;
}

}  // namespace surfcap::io
