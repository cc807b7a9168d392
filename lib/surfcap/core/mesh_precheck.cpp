#include "surfcap/core/mesh_precheck.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
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
    const std::size_t end = content_.find("end_header");
    if (content_.compare(0, 3, "ply") != 0 || end == std::string::npos) fail("not a PLY file (no ply ... end_header)");
    body_ = content_.find('\n', end);
    body_ = body_ == std::string::npos ? content_.size() : body_ + 1;
    std::istringstream header(content_.substr(0, end));
    std::string line;
    while (std::getline(header, line)) {
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (keyword == "format") {
        words >> format_;
      } else if (keyword == "element") {
        PlyElement element;
        if (!(words >> element.name >> element.count) || element.count < 0) fail("bad PLY element line: " + line);
        elements_.push_back(element);
      } else if (keyword == "property") {
        if (elements_.empty()) fail("PLY property before any element");
        std::string type;
        words >> type;
        PlyProperty property;
        if (type == "list") {
          std::string count_type, item_type;
          words >> count_type >> item_type;
          std::tie(property.count_size, property.count_is_float) = ply_type(count_type);
          std::tie(property.size, property.is_float) = ply_type(item_type);
          if (property.count_size == 0 || property.size == 0) fail("unknown PLY list type: " + line);
        } else {
          std::tie(property.size, property.is_float) = ply_type(type);
          if (property.size == 0) fail("unknown PLY property type: " + line);
        }
        elements_.back().properties.push_back(property);
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
        next();
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
            if (property.is_float && !std::isfinite(load_number(position, property.size, true, swap)))
              fail("NaN/Inf value in " + element.name + " " + std::to_string(record));
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
  if (records.empty() || records[0].second[0].find("OFF") == std::string::npos) fail("not an OFF file (no OFF keyword)");
  if (std::find(records[0].second.begin(), records[0].second.end(), "BINARY") != records[0].second.end()) return {};
  // The counts follow the keyword, on its line or the next.
  std::vector<std::string> header(records[0].second.begin() + 1, records[0].second.end());
  std::size_t next = 1;
  if (header.empty()) {
    if (records.size() < 2) fail("truncated OFF header");
    header = records[1].second;
    next = 2;
  }
  double value = 0;
  auto check_numbers = [&](const std::pair<long, std::vector<std::string>>& record, std::size_t minimum) {
    if (record.second.size() < minimum) fail("line " + std::to_string(record.first) + ": too few values");
    for (const auto& token : record.second)
      if (!parse_finite(token, value))
        fail("NaN/Inf or malformed number '" + token + "' at line " + std::to_string(record.first));
  };
  check_numbers({records[next - 1].first, header}, 2);
  MeshFileCounts counts{std::stol(header[0]), std::stol(header[1])};
  if (counts.vertices < 0 || counts.faces < 0) fail("negative element counts in the OFF header");
  if (records.size() < next + static_cast<std::size_t>(counts.vertices + counts.faces))
    fail("truncated: the header declares " + std::to_string(counts.vertices) + " vertices and " +
         std::to_string(counts.faces) + " faces, the file has " + std::to_string(records.size() - next) +
         " data lines");
  for (long v = 0; v < counts.vertices; ++v) check_numbers(records[next + static_cast<std::size_t>(v)], 3);
  for (long f = 0; f < counts.faces; ++f) {
    const auto& record = records[next + static_cast<std::size_t>(counts.vertices + f)];
    check_numbers(record, 1);
    const double n = std::stod(record.second[0]);
    if (n < 1 || n > kMaxPolygon || record.second.size() < 1 + static_cast<std::size_t>(n))
      fail("bad polygon at line " + std::to_string(record.first));
  }
  return counts;
}

}  // namespace

MeshFileCounts precheck_mesh_file(const std::filesystem::path& path, const std::string& extension,
                                  std::optional<long> frame) {
  if (extension == ".ply") return PlyChecker(path, frame).run();
  if (extension == ".off") return precheck_off(path, frame);
  return {};
}

}  // namespace surfcap::core
