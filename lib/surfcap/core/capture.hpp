#pragma once
// The capture folder (DESIGN §3.1, docs/formats.md): capture.json + cameras.json + per-frame
// reconstructions and optional camera images. Read by surfcap-align, written by surfcap-synth.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace surfcap::core {

/// OpenCV pinhole camera: x_cam = R·X + t, pixel = K·(distort(x_cam / z)).
struct CaptureCamera {
  std::string name;
  int width = 0, height = 0;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 5, 1> distortion = Eigen::Matrix<double, 5, 1>::Zero();  ///< k1 k2 p1 p2 k3
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

struct CaptureSequence {
  std::string name;
  std::string frames;  ///< pattern relative to the capture folder, e.g. "walk/mesh/{frame:06d}.ply"
  std::string images;  ///< e.g. "walk/images/{camera}/{frame:06d}.png"; empty: no images
  int first = 0;
  int count = 0;
};

struct Capture {
  std::filesystem::path folder;  ///< where capture.json is
  std::string name;
  std::string units = "m";
  std::string up = "y";
  double fps = 25.0;
  std::vector<CaptureCamera> cameras;
  std::vector<CaptureSequence> sequences;

  long total_frames() const;
  int sequence_index(const std::string& name) const;  ///< -1 if absent
  /// Frame numbers run first..first+count-1; `frame` is the number, not the offset.
  std::filesystem::path mesh_path(int sequence, int frame) const;
  std::filesystem::path image_path(int sequence, int frame, int camera) const;
};

/// Expands "{frame:06d}", "{frame}" and "{camera}" in a frame pattern.
std::string expand_pattern(const std::string& pattern, int frame, const std::string& camera = {});

/// Reads capture.json (a path to the file or its folder) and its cameras.json, checking the
/// format, names, counts, patterns and calibrations (bad_input naming the file).
Capture read_capture(const std::filesystem::path& path);

/// Checks that every frame's mesh exists and, where images are declared, that each camera's image
/// exists and has the camera's size (PNG header). The first problem is a bad_input naming the
/// file and frame; a missing file is bad_input too (the capture is incomplete).
void check_capture_files(const Capture& capture);

/// Writes capture.json and (if there are cameras) cameras.json into capture.folder, atomically.
void write_capture(const Capture& capture);

/// cameras.json (`surfcap.cameras/1`) on its own; read_capture and write_capture use these.
std::vector<CaptureCamera> read_cameras(const std::filesystem::path& path);
void write_cameras(const std::filesystem::path& path, const std::vector<CaptureCamera>& cameras);

/// Width and height from a PNG file's IHDR chunk; bad_input if it is not a PNG.
std::pair<int, int> png_size(const std::filesystem::path& path, std::optional<long> frame = std::nullopt);

}  // namespace surfcap::core
