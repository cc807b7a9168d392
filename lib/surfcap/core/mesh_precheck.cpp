#include "surfcap/core/mesh_precheck.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <sstream>
#include <vector>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::core {
namespace {

constexpr long kMaxPolygon = 1024;  // longer "polygons" are corruption

struct PlyProperty {
  int size = 0;          // scalar: its size; list: the item size
  int count_size = 0;    // list: size of the count; 0 for scalars
  bool is_float = false; // scalar or list item type
  bool count_is_float = false;
  bool colour = false;  // a float colour channel: OpenMesh converts it to 8 bits, so it must be in [0, 1]
};

struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> properties;
};

/// Size in bytes of a PLY type name and whether it is a floating-point type; 0 if unknown.
std::pair<int, bool> ply_type(const std::string& name) {
  if (name == "char" || name == "uchar" || name == "int8" || name == "uint8") return {1, false};
  if (name == "short" || name == "ushort" || name == "int16" || name == "uint16") return {2, false};
  if (name == "int" || name == "uint" || name == "int32" || name == "uint32") return {4, false};
  if (name == "float" || name == "float32") return {4, true};
  if (name == "double" || name == "float64") return {8, true};
  return {0, false};
}

bool parse_finite(const std::string& token, double& value) {
  const char* begin = token.c_str();
  char* end = nullptr;
  value = std::strtod(begin, &end);
  return end != begin && *end == '\0' && std::isfinite(value);
}

class PlyChecker {
 public:
  PlyChecker(const std::filesystem::path& path, std::optional<long> frame) : path_(path), frame_(frame) {}

  MeshFileCounts run() {
    content_ = read_file(path_);
    parse_header();
    MeshFileCounts counts;
    for (const auto& element : elements_) {
      if (element.name == "vertex") counts.vertices = element.count;
      if (element.name == "face") counts.faces = element.count;
    }
    if (counts.vertices < 0) fail("PLY header declares no vertex element");
    if (format_ == "ascii")
      walk_ascii();
    else
      walk_binary(format_ == "binary_big_endian");
    return counts;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw bad_input(path_, what, frame_); }

  void parse_header() {
    // "end_header" must stand on its own line (OpenMesh loops forever on some headers without it).
    static const std::regex end_line("\nend_header[ \t\r]*(\n|$)");
    std::smatch end_match;
    const std::size_t header_limit = std::min<std::size_t>(content_.size(), 1 << 16);
    const std::string head = content_.substr(0, header_limit);
    if (content_.compare(0, 4, "ply\n") != 0 && content_.compare(0, 5, "ply\r\n") != 0)
      fail("not a PLY file (it must start with a 'ply' line)");
    if (!std::regex_search(head, end_match, end_line)) fail("not a PLY file (no end_header line)");
    const std::size_t end = static_cast<std::size_t>(end_match.position(0)) + 1;
    body_ = static_cast<std::size_t>(end_match.position(0) + end_match.length(0));
    // Every header line must be one OpenMesh understands: it loops forever on some others.
    std::istringstream header(content_.substr(0, end));
    std::string line;
    std::getline(header, line);  // "ply"
    long line_number = 1;
    while (std::getline(header, line)) {
      ++line_number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::istringstream words(line);
      std::vector<std::string> tokens;
      for (std::string token; words >> token;) tokens.push_back(token);
      auto bad = [&] { fail("PLY header line " + std::to_string(line_number) + " is not understood: '" + line + "'"); };
      if (tokens.empty()) bad();
      const std::string& keyword = tokens[0];
      if (keyword == "comment" || keyword == "obj_info") continue;
      if (keyword == "format") {
        if (tokens.size() != 3 || tokens[2] != "1.0") bad();
        format_ = tokens[1];
      } else if (keyword == "element") {
        PlyElement element;
        element.name = tokens.size() == 3 ? tokens[1] : "";
        double count = -1;
        if (tokens.size() != 3 || !parse_finite(tokens[2], count) || count < 0 || count > 1e9 || count != std::floor(count))
          bad();
        element.count = static_cast<long>(count);
        elements_.push_back(element);
      } else if (keyword == "property") {
        if (elements_.empty()) fail("PLY property before any element");
        PlyProperty property;
        if (tokens.size() == 5 && tokens[1] == "list") {
          std::tie(property.count_size, property.count_is_float) = ply_type(tokens[2]);
          std::tie(property.size, property.is_float) = ply_type(tokens[3]);
          if (property.count_size == 0 || property.size == 0) bad();
        } else if (tokens.size() == 3) {
          std::tie(property.size, property.is_float) = ply_type(tokens[1]);
          if (property.size == 0) bad();
          static const char* channels[] = {"red", "green", "blue", "alpha", "r", "g", "b", "a",
                                           "diffuse_red", "diffuse_green", "diffuse_blue"};
          property.colour = property.is_float &&
                            std::find(std::begin(channels), std::end(channels), tokens[2]) != std::end(channels);
        } else {
          bad();
        }
        elements_.back().properties.push_back(property);
      } else {
        bad();
      }
    }
    if (format_ != "ascii" && format_ != "binary_little_endian" && format_ != "binary_big_endian")
      fail("unknown PLY format '" + format_ + "'");
  }

  void walk_ascii() {
    std::size_t position = body_;
    long line_number = static_cast<long>(std::count(content_.begin(), content_.begin() + body_, '\n'));
    std::vector<std::string> tokens;
    for (const auto& element : elements_) {
      for (long record = 0; record < element.count; ++record) {
        // Next non-empty line.
        std::string line;
        do {
          if (position >= content_.size())
            fail("truncated: the header declares " + std::to_string(element.count) + " " + element.name +
                 " elements, the file ends at " + element.name + " " + std::to_string(record));
          const std::size_t newline = content_.find('\n', position);
          const std::size_t stop = newline == std::string::npos ? content_.size() : newline;
          line = content_.substr(position, stop - position);
          position = stop + 1;
          ++line_number;
        } while (line.find_first_not_of(" \t\r") == std::string::npos);
        check_ascii_record(element, line, line_number, tokens);
      }
    }
  }

  void check_ascii_record(const PlyElement& element, const std::string& line, long line_number,
                          std::vector<std::string>& tokens) const {
    tokens.clear();
    std::istringstream words(line);
    for (std::string token; words >> token;) tokens.push_back(token);
    std::size_t index = 0;
    auto next = [&]() -> double {
      if (index >= tokens.size())
        fail("line " + std::to_string(line_number) + ": too few values for a " + element.name + " element");
      double value = 0;
      if (!parse_finite(tokens[index], value))
        fail("NaN/Inf or malformed number '" + tokens[index] + "' at line " + std::to_string(line_number));
      ++index;
      return value;
    };
    for (const auto& property : element.properties) {
      if (property.count_size == 0) {
        const double value = next();
        if (property.colour && !(value >= 0 && value <= 1))
          fail("colour value " + tokens[index - 1] + " outside [0, 1] at line " + std::to_string(line_number));
        continue;
      }
      const double count = next();
      if (count < 0 || count > kMaxPolygon || count != std::floor(count))
        fail("line " + std::to_string(line_number) + ": bad list length " + tokens[index - 1]);
      for (long k = 0; k < static_cast<long>(count); ++k) next();
    }
  }

  template <class T>
  T load(std::size_t offset, bool swap) const {
    T value;
    std::memcpy(&value, content_.data() + offset, sizeof(T));
    if (swap) {
      auto* bytes = reinterpret_cast<unsigned char*>(&value);
      std::reverse(bytes, bytes + sizeof(T));
    }
    return value;
  }

  double load_number(std::size_t offset, int size, bool is_float, bool swap) const {
    switch (size) {
      case 1: return static_cast<double>(static_cast<unsigned char>(content_[offset]));
      case 2: return load<std::uint16_t>(offset, swap);
      case 4: return is_float ? static_cast<double>(load<float>(offset, swap)) : load<std::uint32_t>(offset, swap);
      default: return is_float ? load<double>(offset, swap) : static_cast<double>(load<std::uint64_t>(offset, swap));
    }
  }

  void walk_binary(bool big_endian) {
    const bool swap = big_endian != (std::endian::native == std::endian::big);
    std::size_t position = body_;
    for (const auto& element : elements_) {
      for (long record = 0; record < element.count; ++record) {
        for (const auto& property : element.properties) {
          auto need = [&](std::size_t bytes) {
            if (position + bytes > content_.size())
              fail("truncated: the file ends inside " + element.name + " " + std::to_string(record) + " of " +
                   std::to_string(element.count));
          };
          if (property.count_size == 0) {
            need(static_cast<std::size_t>(property.size));
            if (property.is_float) {
              const double value = load_number(position, property.size, true, swap);
              if (!std::isfinite(value)) fail("NaN/Inf value in " + element.name + " " + std::to_string(record));
              if (property.colour && !(value >= 0 && value <= 1))
                fail("colour value outside [0, 1] in " + element.name + " " + std::to_string(record));
            }
            position += static_cast<std::size_t>(property.size);
            continue;
          }
          need(static_cast<std::size_t>(property.count_size));
          const double count = load_number(position, property.count_size, property.count_is_float, swap);
          if (!(count >= 0 && count <= kMaxPolygon))
            fail("bad list length in " + element.name + " " + std::to_string(record) + " (corrupt file)");
          position += static_cast<std::size_t>(property.count_size);
          need(static_cast<std::size_t>(count) * static_cast<std::size_t>(property.size));
          position += static_cast<std::size_t>(count) * static_cast<std::size_t>(property.size);
        }
      }
    }
  }

  std::filesystem::path path_;
  std::optional<long> frame_;
  std::string content_;
  std::string format_;
  std::size_t body_ = 0;
  std::vector<PlyElement> elements_;
};

MeshFileCounts precheck_off(const std::filesystem::path& path, std::optional<long> frame) {
  // Non-empty lines after stripping comments, each as tokens with its line number.
  std::istringstream lines(read_file(path));
  std::vector<std::pair<long, std::vector<std::string>>> records;
  std::string line;
  for (long number = 1; std::getline(lines, line); ++number) {
    std::istringstream words(line.substr(0, line.find('#')));
    std::vector<std::string> tokens;
    for (std::string word; words >> word;) tokens.push_back(word);
    if (!tokens.empty()) records.emplace_back(number, std::move(tokens));
  }
  auto fail = [&](const std::string& what) -> void { throw bad_input(path, what, frame); };
  // The keyword line ([ST][C][N]OFF [BINARY]) stands alone; OpenMesh reads the counts from the next.
  static const std::regex keyword("(ST)?C?N?OFF");
  if (records.empty() || !std::regex_match(records[0].second[0], keyword))
    fail("not a 3-D OFF file (the first line must be [ST][C][N]OFF)");
  if (records[0].second.size() == 2 && records[0].second[1] == "BINARY") return {};
  if (records[0].second.size() != 1) fail("the OFF keyword line must hold only the keyword");
  if (records.size() < 2) fail("truncated OFF header");
  const std::vector<std::string> header = records[1].second;
  const std::size_t next = 2;
  double value = 0;
  auto check_numbers = [&](const std::pair<long, std::vector<std::string>>& record, std::size_t minimum) {
    if (record.second.size() < minimum) fail("line " + std::to_string(record.first) + ": too few values");
    for (const auto& token : record.second)
      if (!parse_finite(token, value))
        fail("NaN/Inf or malformed number '" + token + "' at line " + std::to_string(record.first));
  };
  check_numbers({records[next - 1].first, header}, 2);
  auto count = [&](const std::string& token) {
    double number = 0;
    parse_finite(token, number);
    if (number < 0 || number > 1e9 || number != std::floor(number)) fail("bad element count '" + token + "' in the OFF header");
    return static_cast<long>(number);
  };
  MeshFileCounts counts{count(header[0]), count(header[1])};
  if (records.size() < next + static_cast<std::size_t>(counts.vertices + counts.faces))
    fail("truncated: the header declares " + std::to_string(counts.vertices) + " vertices and " +
         std::to_string(counts.faces) + " faces, the file has " + std::to_string(records.size() - next) +
         " data lines");
  for (long v = 0; v < counts.vertices; ++v) {
    const auto& record = records[next + static_cast<std::size_t>(v)];
    check_numbers(record, 3);
    // Values after x y z (normals, colours, texture coordinates) reach 8-bit colour casts.
    for (std::size_t k = 3; k < record.second.size(); ++k) {
      parse_finite(record.second[k], value);
      if (!(value >= -1 && value <= 255)) fail("vertex value " + record.second[k] + " out of range at line " + std::to_string(record.first));
    }
  }
  for (long f = 0; f < counts.faces; ++f) {
    const auto& record = records[next + static_cast<std::size_t>(counts.vertices + f)];
    check_numbers(record, 1);
    double n = 0;
    parse_finite(record.second[0], n);
    if (n < 1 || n > kMaxPolygon || n != std::floor(n) || record.second.size() < 1 + static_cast<std::size_t>(n))
      fail("bad polygon at line " + std::to_string(record.first));
  }
  return counts;
}

/// OBJ has no header; its vertex lines must hold finite numbers, and colour values after the
/// coordinates ("v x y z r g b", which OpenMesh converts to 8 bits) must lie in [0, 1].
void precheck_obj(const std::filesystem::path& path, std::optional<long> frame) {
  std::istringstream lines(read_file(path));
  std::string line;
  long counts[3] = {0, 0, 0};  // v, vt, vn seen so far
  static const std::regex reference(R"((-?\d{1,9})(?:/(-?\d{1,9})?(?:/(-?\d{1,9}))?)?)");
  for (long number = 1; std::getline(lines, line); ++number) {
    auto fail = [&](const std::string& what) { throw bad_input(path, what + " at line " + std::to_string(number), frame); };
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "v" || keyword == "vt" || keyword == "vn" || keyword == "vc") {
      // "vc r g b" is OpenMesh's per-vertex colour line: every value of it is a colour.
      const int first_colour = keyword == "v" ? 3 : keyword == "vc" ? 0 : -1;
      int index = 0;
      for (std::string token; words >> token; ++index) {
        double value = 0;
        if (!parse_finite(token, value)) fail("NaN/Inf or malformed number '" + token + "'");
        if (first_colour >= 0 && index >= first_colour && !(value >= 0 && value <= 1))
          fail("vertex colour " + token + " outside [0, 1]");
      }
      if (keyword != "vc") ++counts[keyword == "v" ? 0 : keyword == "vt" ? 1 : 2];
    } else if (keyword == "f") {
      // OpenMesh indexes its arrays with these without checking: each must name an earlier element.
      for (std::string token; words >> token;) {
        std::smatch m;
        if (!std::regex_match(token, m, reference)) fail("malformed face vertex '" + token + "'");
        for (int k = 0; k < 3; ++k) {
          if (!m[k + 1].matched) continue;
          const long index = std::stol(m[k + 1].str());
          const long resolved = index < 0 ? counts[k] + index + 1 : index;
          if (resolved < 1 || resolved > counts[k]) fail("face vertex '" + token + "' refers to a missing element");
        }
      }
    }
  }
}

}  // namespace

MeshFileCounts precheck_mesh_file(const std::filesystem::path& path, const std::string& extension,
                                  std::optional<long> frame) {
  if (extension == ".ply") return PlyChecker(path, frame).run();
  if (extension == ".off") return precheck_off(path, frame);
  precheck_obj(path, frame);
  return {};
}

}  // namespace surfcap::core
