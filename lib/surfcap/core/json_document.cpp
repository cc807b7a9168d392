#include "surfcap/core/json_document.hpp"

#include <algorithm>
#include <regex>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"

namespace surfcap::core {

std::string format_tag(std::string_view kind, int version) {
  return "surfcap." + std::string(kind) + "/" + std::to_string(version);
}

std::string json_error_text(const nlohmann::json::exception& error) {
  const std::string text = error.what();
  const std::size_t end = text.rfind("] ", 60);
  return text.rfind("[json.exception.", 0) == 0 && end != std::string::npos ? text.substr(end + 2) : text;
}

namespace {

/// "line L, column C" of a byte offset, for a person.
std::string line_and_column(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(offset), '\n');
  const std::size_t last_newline = text.rfind('\n', offset == 0 ? 0 : offset - 1);
  const std::size_t column = last_newline == std::string_view::npos ? offset : offset - last_newline - 1;
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

/// Refuses arrays/objects nested deeper than kMaxJsonDepth before the parser (or anything
/// recursive over the parsed value: copies, dumps, destructors) sees them.
void check_nesting_depth(std::string_view text, const std::filesystem::path& source) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw bad_input(source, "invalid JSON at " + line_and_column(text, i) + ": nested deeper than " +
                                    std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

}  // namespace

Json parse_json_text(std::string_view text, const std::filesystem::path& source) {
  check_nesting_depth(text, source);
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::out_of_range& e) {  // e.g. a number too large for a double
    throw bad_input(source, "invalid JSON: " + json_error_text(e));
  } catch (const nlohmann::json::parse_error& e) {
    throw bad_input(source, "invalid JSON at " + line_and_column(text, e.byte) + ": " + json_error_text(e));
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(source, "invalid JSON: " + json_error_text(e));
  }
}

Json read_json_file(const std::filesystem::path& path) { return parse_json_text(read_file(path), path); }

Json read_json_document(const std::filesystem::path& path, std::string_view kind, int max_version) {
  Json document = read_json_file(path);
  if (!document.is_object()) throw bad_input(path, "expected a JSON object");
  const auto it = document.find("format");
  if (it == document.end() || !it->is_string())
    throw bad_input(path, "missing \"format\": expected \"" + format_tag(kind, max_version) + "\"");
  const std::string tag = *it;
  static const std::regex tag_re(R"(surfcap\.([a-z_]+)/([0-9]{1,6}))");
  std::smatch m;
  if (!std::regex_match(tag, m, tag_re))
    throw bad_input(path, "\"format\" is \"" + tag + "\", expected \"" + format_tag(kind, max_version) + "\"");
  if (m[1].str() != kind)
    throw bad_input(path, "is a surfcap." + m[1].str() + " file, expected surfcap." + std::string(kind));
  const int version = std::stoi(m[2]);
  if (version < 1 || version > max_version)
    throw bad_input(path, "format version " + std::to_string(version) + " of surfcap." + std::string(kind) +
                              " is newer than this build reads (up to " + std::to_string(max_version) +
                              "); upgrade surfcap");
  return document;
}

int document_version(const Json& document) {
  const std::string tag = document.at("format");
  return std::stoi(tag.substr(tag.rfind('/') + 1));
}

void write_json_file(const std::filesystem::path& path, const Json& document) {
  write_file_atomically(path, document.dump(2) + "\n");
}

void check_integer_field(const Json& value, std::string_view key, const std::filesystem::path& file,
                         std::int64_t min, std::uint64_t max) {
  const std::string field = "field \"" + std::string(key) + "\"";
  if (value.is_number_float() || value.is_boolean())
    throw bad_input(file, field + " has the wrong type: an integer is expected, got " + value.dump());
  bool in_range = true;
  if (value.is_number_unsigned()) {
    in_range = value.get<std::uint64_t>() <= max;
  } else if (value.is_number_integer()) {
    const std::int64_t v = value.get<std::int64_t>();
    in_range = v >= min && (v < 0 || static_cast<std::uint64_t>(v) <= max);
  }
  if (!in_range)
    throw bad_input(file, field + " must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) +
                              "], got " + value.dump());
}

}  // namespace surfcap::core
