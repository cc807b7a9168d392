#pragma once
// A folder of numbered reconstructions (and optional camera images and a calibration) turned into
// a capture folder's capture.json, so nobody writes one by hand. docs/formats.md "Importing a
// capture" is normative for the layout.

#include <filesystem>
#include <string>

#include "surfcap/core/capture.hpp"

namespace surfcap::io {

struct CaptureImportOptions {
  std::filesystem::path folder;      ///< the capture folder: sequences in its subfolders; capture.json goes here
  std::string name;                  ///< capture name; empty: the folder's name
  double fps = 25.0;
  /// cameras.json, a COLMAP text model folder (cameras.txt + images.txt) or an OpenCV FileStorage
  /// file (.yml .yaml .xml); empty: <folder>/cameras.json if present, else no cameras.
  std::filesystem::path calibration;
  double scale = 1.0;                ///< calibration translation units → metres (not for cameras.json)
  std::string mesh_format;           ///< "ply", "obj" or "off" where a folder holds several series; empty: the only one

  void validate() const;  ///< bad_arguments on nonsense values
};

/// Reads a calibration by its form (see CaptureImportOptions::calibration).
std::vector<core::CaptureCamera> read_calibration(const std::filesystem::path& path, double scale);

/// The capture the folder holds: one sequence per subfolder (sorted by name) whose mesh/ folder,
/// or which itself, holds numbered mesh files (<prefix><number>.ply|obj|off, consecutive
/// numbers); images from <sequence>/images/<camera>/<prefix><number>.png when that folder exists.
/// bad_input names the folder or file at fault (a gap in the numbers, an unknown camera...).
core::Capture import_capture(const CaptureImportOptions& options);

}  // namespace surfcap::io
