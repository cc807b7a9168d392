#include "surfcap/core/textured_obj.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <vector>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::core {
namespace {

constexpr int kMaxTextureSide = 8192;  // 8192² RGB: 200 MB decoded, twice while converting

struct Material {
  std::optional<Eigen::Vector3d> diffuse;  // Kd
  std::filesystem::path texture;           // map_Kd; empty: none
  bool clamp = false;
};

/// Diffuse texture, RGB bytes as stored.
struct Texture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  bool clamp = false;

  Eigen::Vector3d texel(int x, int y) const {
    const std::uint8_t* p = rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
    return Eigen::Vector3d(p[0], p[1], p[2]) / 255.0;
  }
  /// Bilinear sample at (u, v), v up, texel centres at ((i + ½)/W, 1 − (j + ½)/H).
  Eigen::Vector3d sample(double u, double v) const {
    // Into [0, 1] first (repeat: the fractional part), so that far-off coordinates stay small.
    u = clamp ? std::clamp(u, 0.0, 1.0) : u - std::floor(u);
    v = clamp ? std::clamp(v, 0.0, 1.0) : v - std::floor(v);
    const double x = u * width - 0.5, y = (1.0 - v) * height - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    auto column = [&](double i) {
      const long k = static_cast<long>(i);
      return static_cast<int>(clamp ? std::clamp(k, 0L, static_cast<long>(width - 1)) : ((k % width) + width) % width);
    };
    auto row = [&](double j) {
      const long k = static_cast<long>(j);
      return static_cast<int>(clamp ? std::clamp(k, 0L, static_cast<long>(height - 1)) : ((k % height) + height) % height);
    };
    const int xa = column(x0), xb = column(x0 + 1), ya = row(y0), yb = row(y0 + 1);
    return (1 - fy) * ((1 - fx) * texel(xa, ya) + fx * texel(xb, ya)) + fy * ((1 - fx) * texel(xa, yb) + fx * texel(xb, yb));
  }
};

/// `name` (as written in `file`) resolved against `file`'s folder; bad_input if it is absolute or
/// leaves that folder.
std::filesystem::path resolve_inside(const std::filesystem::path& file, const std::string& name, const std::string& what,
                                     std::optional<long> frame) {
  const std::filesystem::path relative(name);
  bool escapes = relative.empty() || relative.is_absolute() || relative.has_root_name();
  for (const auto& part : relative) escapes |= part == "..";
  if (escapes)
    throw bad_input(file, what + " '" + name + "' must be a relative path inside the file's folder", frame);
  return file.parent_path() / relative;
}

std::string rest_of_line(std::istringstream& words) {
  std::string rest;
  std::getline(words, rest);
  const auto begin = rest.find_first_not_of(" \t");
  const auto end = rest.find_last_not_of(" \t\r");
  return begin == std::string::npos ? std::string() : rest.substr(begin, end - begin + 1);
}

/// map_Kd's arguments: options (only -clamp changes the sampling; -o, -s, -t would move the
/// texture and are refused), then the file name.
void parse_texture_statement(const std::filesystem::path& mtl, long line, std::string arguments, Material& material,
                             std::optional<long> frame) {
  static const std::map<std::string, int> skipped = {{"-blendu", 1}, {"-blendv", 1}, {"-boost", 1}, {"-mm", 2},
                                                     {"-texres", 1}, {"-bm", 1}, {"-imfchan", 1}, {"-type", 1},
                                                     {"-cc", 1}};
  std::istringstream words(arguments);
  while (words >> std::ws && words.peek() == '-') {
    std::string option;
    words >> option;
    if (option == "-clamp") {
      std::string value;
      words >> value;
      material.clamp = value == "on";
    } else if (const auto it = skipped.find(option); it != skipped.end()) {
      for (int k = 0; k < it->second; ++k) words >> option;
    } else {
      throw bad_input(mtl, "line " + std::to_string(line) + ": map_Kd option '" + option +
                               "' is not supported (texture offsets and scales: bake them into the UVs)", frame);
    }
  }
  const std::string name = rest_of_line(words);
  if (name.empty()) throw bad_input(mtl, "line " + std::to_string(line) + ": map_Kd without a file name", frame);
  material.texture = resolve_inside(mtl, name, "texture", frame);
}

void read_material_library(const std::filesystem::path& mtl, std::map<std::string, Material>& materials,
                           std::optional<long> frame) {
  if (!std::filesystem::exists(mtl)) throw bad_input(mtl, "missing material library", frame);
  if (!std::filesystem::is_regular_file(mtl)) throw bad_input(mtl, "material library is not a file", frame);
  std::istringstream lines(read_file(mtl));
  std::string line, current;
  for (long number = 1; std::getline(lines, line); ++number) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "newmtl") {
      current = rest_of_line(words);
      materials[current] = Material{};
    } else if (keyword == "Kd" || keyword == "map_Kd") {
      Material& material = materials[current];
      if (keyword == "map_Kd") {
        parse_texture_statement(mtl, number, rest_of_line(words), material, frame);
        continue;
      }
      Eigen::Vector3d kd;
      if (!(words >> kd(0) >> kd(1) >> kd(2)) || !kd.allFinite() || kd.minCoeff() < 0 || kd.maxCoeff() > 1)
        throw bad_input(mtl, "line " + std::to_string(number) + ": Kd needs three numbers in [0, 1]", frame);
      material.diffuse = kd;
    }
  }
}

Texture read_texture(const std::filesystem::path& image, bool clamp, std::optional<long> frame) {
  std::string extension = image.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension != ".png") throw bad_input(image, "texture format '" + extension + "' is not supported (PNG)", frame);
  const auto [width, height] = png_size(image, frame);  // also: missing file or not a PNG
  if (width <= 0 || height <= 0 || width > kMaxTextureSide || height > kMaxTextureSide)
    throw bad_input(image, "texture of " + std::to_string(width) + "×" + std::to_string(height) + " pixels (up to " +
                               std::to_string(kMaxTextureSide) + " per side)", frame);
  const cv::Mat bgr = cv::imread(image.string(), cv::IMREAD_COLOR);
  if (bgr.empty() || bgr.type() != CV_8UC3 || bgr.cols != width || bgr.rows != height)
    throw bad_input(image, "texture could not be decoded (corrupt PNG?)", frame);
  Texture texture;
  texture.width = width;
  texture.height = height;
  texture.clamp = clamp;
  texture.rgb.resize(static_cast<std::size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const cv::Vec3b& p = bgr.at<cv::Vec3b>(y, x);
      std::uint8_t* out = texture.rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
      out[0] = p[2], out[1] = p[1], out[2] = p[0];
    }
  return texture;
}

/// The OBJ's content: positions, texture coordinates, triangles with per-corner UV indices
/// (−1: none) and material names.
struct ObjContent {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector2d> uvs;
  std::vector<std::array<int, 3>> triangles, corner_uvs;
  std::vector<int> triangle_material;  // index into material_names; −1: none
  std::vector<std::string> material_names, libraries;
};

long resolve_index(const std::string& token, long count) {
  const long index = std::stol(token);
  return index < 0 ? count + index : index - 1;
}

ObjContent parse_obj(const std::string& text) {
  ObjContent obj;
  std::map<std::string, int> material_index;
  int material = -1;
  std::istringstream lines(text);
  std::string line;
  std::vector<std::pair<int, int>> polygon;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "v") {
      Eigen::Vector3d p;
      words >> p(0) >> p(1) >> p(2);
      obj.positions.push_back(p);
    } else if (keyword == "vt") {
      Eigen::Vector2d t = Eigen::Vector2d::Zero();
      words >> t(0) >> t(1);
      obj.uvs.push_back(t);
    } else if (keyword == "f") {
      polygon.clear();
      for (std::string token; words >> token;) {
        const std::size_t slash = token.find('/');
        const long v = resolve_index(token.substr(0, slash), static_cast<long>(obj.positions.size()));
        long t = -1;
        if (slash != std::string::npos && slash + 1 < token.size() && token[slash + 1] != '/')
          t = resolve_index(token.substr(slash + 1, token.find('/', slash + 1) - slash - 1),
                            static_cast<long>(obj.uvs.size()));
        polygon.emplace_back(static_cast<int>(v), static_cast<int>(t));
      }
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        obj.triangles.push_back({polygon[0].first, polygon[k].first, polygon[k + 1].first});
        obj.corner_uvs.push_back({polygon[0].second, polygon[k].second, polygon[k + 1].second});
        obj.triangle_material.push_back(material);
      }
    } else if (keyword == "usemtl") {
      const std::string name = rest_of_line(words);
      const auto [it, added] = material_index.emplace(name, static_cast<int>(obj.material_names.size()));
      if (added) obj.material_names.push_back(name);
      material = it->second;
    } else if (keyword == "mtllib") {
      for (std::string name; words >> name;) obj.libraries.push_back(name);
    }
  }
  return obj;
}

/// For each vertex, the first vertex at the same position (bit for bit).
std::vector<long> weld_by_position(const std::vector<Eigen::Vector3d>& positions) {
  std::vector<long> order(positions.size());
  std::iota(order.begin(), order.end(), 0L);
  auto key = [&](long v) {
    const auto& p = positions[static_cast<std::size_t>(v)];
    return std::make_tuple(p(0), p(1), p(2), v);
  };
  std::sort(order.begin(), order.end(), [&](long a, long b) { return key(a) < key(b); });
  std::vector<long> first(positions.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const long v = order[i];
    const bool same = i > 0 && positions[static_cast<std::size_t>(order[i - 1])] == positions[static_cast<std::size_t>(v)];
    first[static_cast<std::size_t>(v)] = same ? first[static_cast<std::size_t>(order[i - 1])] : v;
  }
  return first;
}

}  // namespace

bool obj_uses_materials(const std::string& obj_text) {
  bool library = false, use = false;
  std::istringstream lines(obj_text);
  for (std::string line; std::getline(lines, line) && !(library && use);) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    library |= keyword == "mtllib";
    use |= keyword == "usemtl";
  }
  return library && use;
}

Mesh read_textured_obj(const std::filesystem::path& path, const std::string& obj_text, std::optional<long> frame) {
  const ObjContent obj = parse_obj(obj_text);
  std::map<std::string, Material> library;
  for (const auto& name : obj.libraries) read_material_library(resolve_inside(path, name, "material library", frame), library, frame);
  // Each used material: its texture (decoded once) or its diffuse colour.
  std::vector<std::optional<Texture>> textures(obj.material_names.size());
  std::vector<std::optional<Eigen::Vector3d>> diffuse(obj.material_names.size());
  for (std::size_t m = 0; m < obj.material_names.size(); ++m) {
    const auto it = library.find(obj.material_names[m]);
    if (it == library.end())
      throw bad_input(path, "material '" + obj.material_names[m] + "' is not defined in its material libraries", frame);
    if (!it->second.texture.empty()) textures[m] = read_texture(it->second.texture, it->second.clamp, frame);
    diffuse[m] = it->second.diffuse;
  }

  const std::vector<long> first = weld_by_position(obj.positions);
  std::vector<long> index(obj.positions.size(), -1);
  long kept = 0;
  for (std::size_t v = 0; v < obj.positions.size(); ++v)
    if (first[v] == static_cast<long>(v)) index[v] = kept++;
  Mesh mesh;
  mesh.V.resize(kept, 3);
  for (std::size_t v = 0; v < obj.positions.size(); ++v)
    if (index[v] >= 0) mesh.V.row(index[v]) = obj.positions[v].transpose();
  mesh.F.resize(static_cast<long>(obj.triangles.size()), 3);
  Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(kept, 3);
  Eigen::VectorXd counts = Eigen::VectorXd::Zero(kept);
  std::vector<char> referenced(static_cast<std::size_t>(kept), 0);
  for (std::size_t f = 0; f < obj.triangles.size(); ++f) {
    const int m = obj.triangle_material[f];
    for (int k = 0; k < 3; ++k) {
      const long v = index[static_cast<std::size_t>(first[static_cast<std::size_t>(obj.triangles[f][k])])];
      mesh.F(static_cast<long>(f), k) = static_cast<int>(v);
      referenced[static_cast<std::size_t>(v)] = 1;
      std::optional<Eigen::Vector3d> colour;
      const int t = obj.corner_uvs[f][k];
      if (m >= 0 && textures[static_cast<std::size_t>(m)] && t >= 0)
        colour = textures[static_cast<std::size_t>(m)]->sample(obj.uvs[static_cast<std::size_t>(t)](0),
                                                               obj.uvs[static_cast<std::size_t>(t)](1));
      else if (m >= 0)
        colour = diffuse[static_cast<std::size_t>(m)];
      if (!colour) continue;
      sums.row(v) += colour->transpose();
      counts(v) += 1;
    }
  }
  if (counts.maxCoeff() > 0) {
    long uncoloured = 0;
    mesh.colors = Eigen::MatrixXd::Constant(kept, 3, 0.5);
    for (long v = 0; v < kept; ++v) {
      if (counts(v) > 0) mesh.colors.row(v) = sums.row(v) / counts(v);
      else uncoloured += referenced[static_cast<std::size_t>(v)];
    }
    if (uncoloured > 0)
      spdlog::warn("{}: {} vertices have no textured or coloured corner (grey)", where(path, frame), uncoloured);
  }
  return mesh;
}

}  // namespace surfcap::core
