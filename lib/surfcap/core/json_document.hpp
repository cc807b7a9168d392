#pragma once
// surfcap metadata files: JSON objects carrying "format": "surfcap.<kind>/<version>".

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace surfcap::core {

using Json = nlohmann::json;

/// "surfcap.<kind>/<version>".
std::string format_tag(std::string_view kind, int version);

/// Parses `path` and checks its "format": the kind must match and the version must be
/// 1..max_version. bad_input (3) otherwise, e.g. a file written by a newer surfcap.
Json read_json_document(const std::filesystem::path& path, std::string_view kind, int max_version);
/// Version of a document already checked by read_json_document.
int document_version(const Json& document);

/// Parses any JSON file (configs without a format tag); bad_input with line/column on syntax errors.
Json read_json_file(const std::filesystem::path& path);

/// Writes `document` atomically, pretty-printed (2 spaces) with a trailing newline. Keys come out
/// sorted, so the bytes depend only on the content.
void write_json_file(const std::filesystem::path& path, const Json& document);

/// Typed field access with errors naming the file and the JSON pointer of the field. An integer
/// T takes only a JSON integer within T's range: a float (2.5, and 2.0 too: JSON numbers with a
/// fraction or exponent are floats) or a boolean is bad input, never truncated or converted.
template <class T>
T get_field(const Json& object, std::string_view key, const std::filesystem::path& file);

/// For get_field of an integer type: bad_input naming `file` and `key` when `value` is a float, a
/// boolean or an integer outside [min, max]. Other types are left to the JSON library's check.
void check_integer_field(const Json& value, std::string_view key, const std::filesystem::path& file,
                         std::int64_t min, std::uint64_t max);

}  // namespace surfcap::core

#include "surfcap/core/json_document_impl.hpp"
