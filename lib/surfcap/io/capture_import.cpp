#include "surfcap/io/capture_import.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>

#include "surfcap/core/error.hpp"
#include "surfcap/io/camera_import.hpp"

namespace surfcap::io {
namespace {

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

/// Files <prefix><number>.<extension> of one folder sharing prefix and extension.
struct NumberedSeries {
  std::string prefix, extension;
  std::map<long, int> digits;  ///< frame number → digits in its name

  /// "{frame:06d}" when every name has the same number of digits, "{frame}" when none is padded.
  std::string field(const std::filesystem::path& folder) const {
    const int width = digits.begin()->second;
    if (std::all_of(digits.begin(), digits.end(), [&](const auto& entry) { return entry.second == width; }))
      return width > 1 ? "{frame:0" + std::to_string(width) + "d}" : "{frame}";
    for (const auto& [number, count] : digits)
      if (static_cast<int>(std::to_string(number).size()) != count)
        throw core::bad_input(folder, "numbered files mix zero-padded and unpadded numbers (" + prefix + "…" +
                                          extension + ")");
    return "{frame}";
  }
  long first() const { return digits.begin()->first; }
  long last() const { return digits.rbegin()->first; }
};

/// The numbered series of `folder` whose extension is one of `extensions` (lower case, with dot).
std::vector<NumberedSeries> numbered_series(const std::filesystem::path& folder, const std::vector<std::string>& extensions) {
  static const std::regex numbered(R"((.*?)(\d{1,9})(\.[A-Za-z]+))");
  std::map<std::pair<std::string, std::string>, NumberedSeries> series;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    const std::string file = entry.path().filename().string();
    std::smatch m;
    if (!std::regex_match(file, m, numbered)) continue;
    if (std::find(extensions.begin(), extensions.end(), lowercase(m[3])) == extensions.end()) continue;
    if (m[1].str().find_first_of("{}") != std::string::npos)
      throw core::bad_input(entry.path(), "file names with '{' or '}' cannot be named by a frame pattern");
    NumberedSeries& s = series[{m[1], m[3]}];
    s.prefix = m[1];
    s.extension = m[3];
    const long number = std::stol(m[2]);
    if (!s.digits.emplace(number, static_cast<int>(m[2].length())).second)
      throw core::bad_input(entry.path(), "frame " + std::to_string(number) + " appears twice in its folder");
  }
  std::vector<NumberedSeries> out;
  for (auto& [key, s] : series) out.push_back(std::move(s));
  return out;
}

/// The one mesh series of a sequence folder (or the one of `format`).
NumberedSeries mesh_series(const std::filesystem::path& folder, const std::string& format) {
  std::vector<std::string> extensions = {".ply", ".obj", ".off"};
  if (!format.empty()) extensions = {"." + format};
  const auto series = numbered_series(folder, extensions);
  if (series.empty()) return {};
  if (series.size() > 1) {
    std::string list;
    for (const auto& s : series) list += (list.empty() ? "" : ", ") + s.prefix + "<number>" + s.extension;
    throw core::bad_input(folder, "several numbered mesh series (" + list + "): keep one, or choose with --mesh-format");
  }
  const NumberedSeries& s = series.front();
  for (long number = s.first(); number <= s.last(); ++number)
    if (!s.digits.count(number))
      throw core::bad_input(folder, "frame " + std::to_string(number) + " is missing between " + std::to_string(s.first()) +
                                        " and " + std::to_string(s.last()) + " (" + s.prefix + "<number>" + s.extension + ")");
  return s;
}

std::string generic(const std::filesystem::path& path) { return path.generic_string(); }

/// <sequence>/images/<camera>/ → the images pattern; checks the cameras against the calibration.
std::string image_pattern(const std::filesystem::path& capture_folder, const std::filesystem::path& relative,
                          const std::vector<core::CaptureCamera>& cameras) {
  const auto images = capture_folder / relative;
  if (cameras.empty()) throw core::bad_input(images, "camera images but no calibration (--calibration)");
  std::vector<std::string> folders;
  for (const auto& entry : std::filesystem::directory_iterator(images))
    if (entry.is_directory()) folders.push_back(entry.path().filename().string());
  std::sort(folders.begin(), folders.end());
  for (const auto& folder : folders)
    if (std::none_of(cameras.begin(), cameras.end(), [&](const auto& c) { return c.name == folder; }))
      throw core::bad_input(images / folder, "images of a camera the calibration does not have");
  std::string pattern;
  for (const auto& camera : cameras) {
    if (!std::filesystem::is_directory(images / camera.name))
      throw core::bad_input(images, "no images of camera '" + camera.name + "' (a folder " + camera.name + "/)");
    const auto series = numbered_series(images / camera.name, {".png"});
    if (series.size() != 1)
      throw core::bad_input(images / camera.name, series.empty() ? "no numbered PNG images" : "several numbered PNG series");
    const std::string own = generic(relative / "{camera}" / (series[0].prefix + series[0].field(images / camera.name) +
                                                             series[0].extension));
    if (!pattern.empty() && own != pattern)
      throw core::bad_input(images / camera.name, "images named unlike the other cameras' (" + pattern + ")");
    pattern = own;
  }
  return pattern;
}

}  // namespace

void CaptureImportOptions::validate() const {
  if (!(fps > 0) || !std::isfinite(fps)) throw core::bad_arguments("--fps must be positive");
  if (!(scale > 0) || !std::isfinite(scale)) throw core::bad_arguments("--scale must be positive");
  if (!mesh_format.empty() && mesh_format != "ply" && mesh_format != "obj" && mesh_format != "off")
    throw core::bad_arguments("--mesh-format must be ply, obj or off");
}

std::vector<core::CaptureCamera> read_calibration(const std::filesystem::path& path, double scale) {
  if (!std::filesystem::exists(path)) throw core::io_error(path, "no such file or folder");
  if (std::filesystem::is_directory(path)) {
    auto cameras = read_colmap_cameras(path);
    scale_translations(cameras, scale);
    return cameras;
  }
  const std::string extension = lowercase(path.extension().string());
  if (extension == ".json") {
    if (scale != 1.0) throw core::bad_arguments("--scale applies to COLMAP and OpenCV calibrations, not cameras.json");
    return core::read_cameras(path);
  }
  if (extension == ".yml" || extension == ".yaml" || extension == ".xml") {
    auto cameras = read_opencv_cameras(path);
    scale_translations(cameras, scale);
    return cameras;
  }
  throw core::bad_arguments("'" + path.string() + "': a calibration is cameras.json, a COLMAP text model folder, or an "
                            "OpenCV .yml/.yaml/.xml file");
}

core::Capture import_capture(const CaptureImportOptions& options) {
  options.validate();
  const auto& folder = options.folder;
  if (!std::filesystem::is_directory(folder)) throw core::io_error(folder, "no such folder");
  core::Capture capture;
  capture.folder = folder;
  capture.name = options.name;
  if (capture.name.empty()) {
    const auto normal = std::filesystem::absolute(folder).lexically_normal();
    capture.name = normal.has_filename() ? normal.filename().string() : normal.parent_path().filename().string();
  }
  capture.fps = options.fps;
  if (!options.calibration.empty()) capture.cameras = read_calibration(options.calibration, options.scale);
  else if (std::filesystem::exists(folder / "cameras.json")) capture.cameras = core::read_cameras(folder / "cameras.json");

  // (sequence name, its folder relative to the capture folder)
  std::vector<std::pair<std::string, std::filesystem::path>> candidates;
  if (std::filesystem::is_directory(folder / "mesh")) {
    candidates.emplace_back(capture.name, std::filesystem::path());
  } else {
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      if (entry.is_directory() && entry.path().filename().string()[0] != '.')
        candidates.emplace_back(entry.path().filename().string(), entry.path().filename());
    std::sort(candidates.begin(), candidates.end());
  }
  for (const auto& [name, relative] : candidates) {
    const bool nested = std::filesystem::is_directory(folder / relative / "mesh");
    const auto mesh_folder = nested ? relative / "mesh" : relative;
    const NumberedSeries series = mesh_series(folder / mesh_folder, options.mesh_format);
    if (series.digits.empty()) continue;  // not a sequence (reports, calibration, ...)
    if (name.empty() || name.find_first_of("/\\ ") != std::string::npos)
      throw core::bad_input(folder / relative, "sequence folder names must be non-empty without spaces");
    core::CaptureSequence sequence;
    sequence.name = name;
    sequence.frames = generic(mesh_folder / (series.prefix + series.field(folder / mesh_folder) + series.extension));
    sequence.first = static_cast<int>(series.first());
    sequence.count = static_cast<int>(series.last() - series.first() + 1);
    if (std::filesystem::is_directory(folder / relative / "images"))
      sequence.images = image_pattern(folder, relative / "images", capture.cameras);
    capture.sequences.push_back(sequence);
  }
  if (capture.sequences.empty())
    throw core::bad_input(folder, "no sequence: expected subfolders holding numbered meshes (walk/mesh/000000.ply, ...)");
  core::check_capture_files(capture);
  return capture;
}

}  // namespace surfcap::io
