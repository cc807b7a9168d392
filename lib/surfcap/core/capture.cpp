#include "surfcap/core/capture.hpp"

#include <Eigen/LU>
#include <fstream>
#include <regex>
#include <set>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/json_integer.hpp"

namespace surfcap::core {
namespace {

template <int Rows, int Cols>
Eigen::Matrix<double, Rows, Cols> read_matrix(const Json& object, const char* key, const std::filesystem::path& file,
                                              const std::string& camera) {
  const auto values = get_field<std::vector<double>>(object, key, file);
  if (values.size() != static_cast<std::size_t>(Rows * Cols))
    throw bad_input(file, "camera '" + camera + "': \"" + key + "\" needs " + std::to_string(Rows * Cols) +
                              " numbers, has " + std::to_string(values.size()));
  Eigen::Matrix<double, Rows, Cols> matrix;
  for (int r = 0; r < Rows; ++r)
    for (int c = 0; c < Cols; ++c) matrix(r, c) = values[static_cast<std::size_t>(r * Cols + c)];
  if (!matrix.allFinite()) throw bad_input(file, "camera '" + camera + "': \"" + key + "\" has NaN/Inf");
  return matrix;
}

Json matrix_json(const Eigen::MatrixXd& matrix) {
  Json values = Json::array();
  for (long r = 0; r < matrix.rows(); ++r)
    for (long c = 0; c < matrix.cols(); ++c) values.push_back(matrix(r, c));
  return values;
}

std::vector<CaptureCamera> parse_cameras(const std::filesystem::path& file) {
  const Json document = read_json_document(file, "cameras", 1);
  std::vector<CaptureCamera> cameras;
  std::set<std::string> names;
  for (const auto& entry : get_field<Json>(document, "cameras", file)) {
    CaptureCamera camera;
    camera.name = name_field(entry, "name", file);  // it names image folders
    if (!names.insert(camera.name).second) throw bad_input(file, "camera '" + camera.name + "' appears twice");
    camera.width = get_field<int>(entry, "width", file);
    camera.height = get_field<int>(entry, "height", file);
    if (camera.width <= 0 || camera.height <= 0 || camera.width > kMaxImageSide || camera.height > kMaxImageSide)
      throw bad_input(file, "camera '" + camera.name + "': bad image size " + std::to_string(camera.width) + "×" +
                                std::to_string(camera.height) + " (1 to " + std::to_string(kMaxImageSide) + " pixels a side)");
    camera.K = read_matrix<3, 3>(entry, "K", file, camera.name);
    camera.R = read_matrix<3, 3>(entry, "R", file, camera.name);
    camera.t = read_matrix<3, 1>(entry, "t", file, camera.name);
    if (entry.contains("dist")) {
      auto dist = get_field<std::vector<double>>(entry, "dist", file);
      if (dist.size() > 5) throw bad_input(file, "camera '" + camera.name + "': \"dist\" has more than 5 values");
      for (std::size_t i = 0; i < dist.size(); ++i)
        camera.distortion(static_cast<long>(i)) =
            check_magnitude(file, "camera '" + camera.name + "': \"dist\"[" + std::to_string(i) + "]", dist[i], 1e3);
    }
    if ((camera.R * camera.R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
        camera.R.determinant() < 0)
      throw bad_input(file, "camera '" + camera.name + "': R is not a rotation");
    for (int k = 0; k < 3; ++k)
      check_magnitude(file, "camera '" + camera.name + "': t[" + std::to_string(k) + "]", camera.t(k), kMaxCoordinate);
    // K = [fx s cx; 0 fy cy; 0 0 1] with fx, fy > 0 is invertible; anything else is not a pinhole camera.
    if (camera.K(1, 0) != 0 || camera.K(2, 0) != 0 || camera.K(2, 1) != 0 || camera.K(2, 2) != 1)
      throw bad_input(file, "camera '" + camera.name + "': K must be upper triangular with K[2][2] = 1");
    if (camera.K(0, 0) <= 0 || camera.K(1, 1) <= 0)
      throw bad_input(file, "camera '" + camera.name + "': focal lengths must be positive");
    if (camera.K.cwiseAbs().maxCoeff() > 1e7)
      throw bad_input(file, "camera '" + camera.name + "': K has an entry beyond 1e7 pixels");
    cameras.push_back(camera);
  }
  if (cameras.empty()) throw bad_input(file, "no cameras");
  return cameras;
}

std::vector<CaptureCamera> read_cameras_checked(const std::filesystem::path& file) {
  try {
    return parse_cameras(file);
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(file, "a field has the wrong type: " + json_error_text(e));
  }
}

}  // namespace

static Capture read_capture_document(const std::filesystem::path& file);

long Capture::total_frames() const {
  long total = 0;
  for (const auto& sequence : sequences) total += sequence.count;
  return total;
}

int Capture::sequence_index(const std::string& wanted) const {
  for (std::size_t i = 0; i < sequences.size(); ++i)
    if (sequences[i].name == wanted) return static_cast<int>(i);
  return -1;
}

std::string expand_pattern(const std::string& pattern, int frame, const std::string& camera) {
  static const std::regex field(R"(\{(frame|camera)(?::0?(\d{1,2})d)?\})");
  std::string out;
  auto begin = pattern.cbegin();
  for (std::sregex_iterator it(pattern.begin(), pattern.end(), field), end; it != end; ++it) {
    const auto& match = *it;
    out.append(begin, match[0].first);
    if (match[1] == "camera") {
      out += camera;
    } else {
      std::string number = std::to_string(frame);
      const std::size_t width = match[2].matched ? std::stoul(match[2].str()) : 0;
      if (number.size() < width) number.insert(0, width - number.size(), '0');
      out += number;
    }
    begin = match[0].second;
  }
  out.append(begin, pattern.cend());
  return out;
}

std::filesystem::path Capture::mesh_path(int sequence, int frame) const {
  return folder / expand_pattern(sequences.at(static_cast<std::size_t>(sequence)).frames, frame);
}

std::filesystem::path Capture::image_path(int sequence, int frame, int camera) const {
  return folder / expand_pattern(sequences.at(static_cast<std::size_t>(sequence)).images, frame,
                                 cameras.at(static_cast<std::size_t>(camera)).name);
}

Capture read_capture(const std::filesystem::path& path) {
  const auto file = std::filesystem::is_directory(path) ? path / "capture.json" : path;
  try {
    return read_capture_document(file);
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(file, "a field has the wrong type: " + json_error_text(e));
  }
}

static Capture read_capture_document(const std::filesystem::path& file) {
  const Json document = read_json_document(file, "capture", 1);
  Capture capture;
  capture.folder = file.parent_path();
  capture.name = document.value("name", capture.folder.filename().string());
  capture.units = document.value("units", std::string("m"));
  capture.up = document.value("up", std::string("y"));
  capture.fps = number_field(document, "fps", file, 0, kMaxFps, 25.0);
  if (capture.units != "m") throw bad_input(file, "units '" + capture.units + "' are not supported (metres: \"m\")");
  if (capture.up != "y") throw bad_input(file, "up axis '" + capture.up + "' is not supported (\"y\")");
  if (!(capture.fps > 0)) throw bad_input(file, "fps must be positive");
  if (document.contains("cameras")) capture.cameras = read_cameras_checked(path_field(document, "cameras", file));
  for (const auto& camera : capture.cameras)  // an image is decoded whole, in several planes
    check_memory(file, "an image of camera '" + camera.name + "' (" + std::to_string(camera.width) + "×" +
                           std::to_string(camera.height) + ")",
                 16.0 * camera.width * camera.height);
  std::set<std::string> names;
  for (const auto& entry : get_field<Json>(document, "sequences", file)) {
    CaptureSequence sequence;
    sequence.name = name_field(entry, "name", file);
    if (!names.insert(sequence.name).second) throw bad_input(file, "sequence '" + sequence.name + "' appears twice");
    sequence.frames = get_field<std::string>(entry, "frames", file);
    if (sequence.frames.find("{frame") == std::string::npos)
      throw bad_input(file, "sequence '" + sequence.name + "': \"frames\" needs a {frame} field");
    sequence.images = entry.value("images", std::string());
    if (!sequence.images.empty() && capture.cameras.empty())
      throw bad_input(file, "sequence '" + sequence.name + "' has images but the capture has no cameras");
    // Frame numbers and camera names expand to one path component each, so one expansion shows
    // where every file of the pattern is.
    resolve_document_path(file, "frames", expand_pattern(sequence.frames, 0));
    if (!sequence.images.empty()) resolve_document_path(file, "images", expand_pattern(sequence.images, 0, "camera"));
    sequence.first = static_cast<int>(integer_field_or(entry, "first", file, 0, 1'000'000'000, 0));
    sequence.count = static_cast<int>(integer_field(entry, "count", file, 1, kMaxFrames));
    capture.sequences.push_back(sequence);
  }
  if (capture.sequences.empty()) throw bad_input(file, "no sequences");
  return capture;
}

std::pair<int, int> png_size(const std::filesystem::path& path, std::optional<long> frame) {
  if (!std::filesystem::exists(path)) throw bad_input(path, "missing image", frame);
  check_regular_file(path, frame);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw bad_input(path, "missing image", frame);
  unsigned char header[24] = {};
  in.read(reinterpret_cast<char*>(header), 24);
  static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (in.gcount() != 24 || !std::equal(signature, signature + 8, header) || std::string(header + 12, header + 16) != "IHDR")
    throw bad_input(path, "not a PNG image", frame);
  auto be32 = [&](int offset) {
    const std::uint32_t value = (std::uint32_t{header[offset]} << 24) | (std::uint32_t{header[offset + 1]} << 16) |
                                (std::uint32_t{header[offset + 2]} << 8) | header[offset + 3];
    return static_cast<int>(std::min<std::uint32_t>(value, 0x7fffffff));
  };
  return {be32(16), be32(20)};
}

void check_capture_files(const Capture& capture) {
  for (std::size_t s = 0; s < capture.sequences.size(); ++s) {
    const auto& sequence = capture.sequences[s];
    for (int frame = sequence.first; frame < sequence.first + sequence.count; ++frame) {
      const auto mesh = capture.mesh_path(static_cast<int>(s), frame);
      if (!std::filesystem::exists(mesh))
        throw bad_input(mesh, "missing frame of sequence '" + sequence.name + "'", frame);
      check_regular_file(mesh, frame);
      if (sequence.images.empty()) continue;
      for (std::size_t c = 0; c < capture.cameras.size(); ++c) {
        const auto image = capture.image_path(static_cast<int>(s), frame, static_cast<int>(c));
        if (!std::filesystem::exists(image))
          throw bad_input(image, "missing image of camera '" + capture.cameras[c].name + "'", frame);
        const auto [width, height] = png_size(image, frame);
        if (width != capture.cameras[c].width || height != capture.cameras[c].height)
          throw bad_input(image, "image is " + std::to_string(width) + "×" + std::to_string(height) + ", camera '" +
                                     capture.cameras[c].name + "' is calibrated for " +
                                     std::to_string(capture.cameras[c].width) + "×" +
                                     std::to_string(capture.cameras[c].height), frame);
      }
    }
  }
}

std::vector<CaptureCamera> read_cameras(const std::filesystem::path& path) { return read_cameras_checked(path); }

void write_cameras(const std::filesystem::path& path, const std::vector<CaptureCamera>& cameras) {
  Json list = Json::array();
  for (const auto& camera : cameras)
    list.push_back({{"name", camera.name}, {"width", camera.width}, {"height", camera.height},
                    {"K", matrix_json(camera.K)}, {"dist", matrix_json(camera.distortion)},
                    {"R", matrix_json(camera.R)}, {"t", matrix_json(camera.t)}});
  write_json_file(path, {{"format", format_tag("cameras", 1)}, {"cameras", list}});
}

void write_capture(const Capture& capture) {
  Json sequences = Json::array();
  for (const auto& sequence : capture.sequences) {
    Json entry = {{"name", sequence.name}, {"frames", sequence.frames}, {"first", sequence.first},
                  {"count", sequence.count}};
    if (!sequence.images.empty()) entry["images"] = sequence.images;
    sequences.push_back(entry);
  }
  Json document = {{"format", format_tag("capture", 1)}, {"name", capture.name}, {"units", capture.units},
                   {"up", capture.up}, {"fps", capture.fps}, {"sequences", sequences}};
  if (!capture.cameras.empty()) {
    write_cameras(capture.folder / "cameras.json", capture.cameras);
    document["cameras"] = "cameras.json";
  }
  write_json_file(capture.folder / "capture.json", document);
}

}  // namespace surfcap::core
