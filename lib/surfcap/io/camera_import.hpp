#pragma once
// Camera calibrations as studios and calibration tools hand them over, turned into the capture
// folder's cameras (core::CaptureCamera: OpenCV pinhole, x_cam = R·X + t, pixel centres at
// integers, distortion k1 k2 p1 p2 k3). docs/formats.md "Importing calibrations" is normative.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/core/capture.hpp"

namespace surfcap::io {

/// COLMAP's text model: `folder`/cameras.txt and `folder`/images.txt. One camera per image,
/// named after the image's folder when its NAME has one ("cam03/000000.png" → cam03), else after
/// its file stem ("cam03.png" → cam03). Models SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL,
/// OPENCV, and FULL_OPENCV when k4 = k5 = k6 = 0. COLMAP puts the centre of the top-left pixel at
/// (0.5, 0.5): the principal point moves by −0.5 px. bad_input names the file and line.
std::vector<core::CaptureCamera> read_colmap_cameras(const std::filesystem::path& folder);

/// OpenCV FileStorage (YAML or XML, what cv::FileStorage writes) with, per camera, K (or
/// camera_matrix), dist (or distortion_coefficients, D; 4, 5, 8, 12 or 14 values, those after k3
/// zero), R (3×3, or a Rodrigues vector) or rvec, t (or T, tvec), and width/height (or
/// image_width/image_height, or image_size [w, h]). Cameras are maps at the top level named by
/// their key, or a sequence "cameras" of maps with a "name", or the top level itself (one camera
/// named after the file stem). bad_input names the file and the camera.
std::vector<core::CaptureCamera> read_opencv_cameras(const std::filesystem::path& file);

/// Multiplies every t by `scale` (calibration units → metres).
void scale_translations(std::vector<core::CaptureCamera>& cameras, double scale);

/// Checks what cameras.json requires (unique file-name-safe names, positive sizes and focal
/// lengths, R a rotation); bad_input names `source` and the camera.
void check_cameras(const std::vector<core::CaptureCamera>& cameras, const std::filesystem::path& source);

/// Pixel of a world point through the full OpenCV model (radial k1 k2 k3, tangential p1 p2).
Eigen::Vector2d project(const core::CaptureCamera& camera, const Eigen::Vector3d& world);

}  // namespace surfcap::io
