#include "surfcap/core/json_document.hpp"

#include <regex>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::core {

std::string format_tag(std::string_view kind, int version) {
  return "surfcap." + std::string(kind) + "/" + std::to_string(version);
}

Json read_json_file(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::out_of_range& e) {  // e.g. a number too large for a double
    throw bad_input(path, std::string("invalid JSON: ") + e.what());
  } catch (const nlohmann::json::parse_error& e) {
    // Turn the byte offset into line:column for a person.
    const std::size_t offset = std::min<std::size_t>(e.byte, text.size());
    const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(offset), '\n');
    const std::size_t last_newline = text.rfind('\n', offset == 0 ? 0 : offset - 1);
    const std::size_t column = last_newline == std::string::npos ? offset : offset - last_newline - 1;
    throw bad_input(path, "invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) +
                              ": " + e.what());
  }
}

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

}  // namespace surfcap::core
