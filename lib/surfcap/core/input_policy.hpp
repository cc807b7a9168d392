#pragma once
// What an input may make a tool do (docs/reliability.md "Input policy"): which paths a document
// may name, which names may become paths, which files may be opened, how much memory a request
// read from a file may claim, and how large a number may be. One place, used by every reader.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::core {

/// Arrays and objects nested deeper than this are bad input (no surfcap document needs more than
/// a handful of levels; a deep nesting would exhaust the stack of recursive JSON code).
constexpr int kMaxJsonDepth = 64;

/// The one JSON parser of surfcap: checks the nesting depth first, then parses. bad_input naming
/// `source` (with line and column) on any error. read_json_file, --config files and the .glb
/// reader use it.
Json parse_json_text(std::string_view text, const std::filesystem::path& source);

/// nlohmann's message without its "[json.exception.type_error.302] " prefix.
std::string json_error_text(const nlohmann::json::exception& error);

/// Runs `read` (which reads fields of a document of `file`) and turns any nlohmann::json exception
/// (a field of the wrong type, a missing key read with .at()) into bad_input naming the file.
template <class Read>
auto read_document_fields(const std::filesystem::path& file, Read&& read) -> decltype(read()) {
  try {
    return read();
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(file, "a field is missing or has the wrong type: " + json_error_text(e));
  }
}

/// Set once per process by ToolApp from --allow-outside-paths and --max-memory.
struct InputPolicy {
  bool allow_outside_paths = false;  ///< documents may name absolute paths and paths leaving their folder
  std::uint64_t max_memory_bytes = 0;  ///< 0: the default, half of the physical memory
};
InputPolicy& input_policy();
/// The effective memory budget in bytes (the option, or half of the physical memory).
std::uint64_t memory_budget();
/// Parses "--max-memory" values: bytes, or a number with K, M, G or T (powers of 1024); 0 = default.
std::uint64_t parse_memory_size(const std::string& text);

/// Largest magnitude of a coordinate, translation or root position read from a file (metres).
constexpr double kMaxCoordinate = 1e5;
/// Largest plausible frame rate (frames per second) and duration (seconds) read from a file.
constexpr double kMaxFps = 1000;
constexpr double kMaxDurationS = 86400;
/// Largest frame count of one sequence, and largest image side in pixels.
constexpr long kMaxFrames = 10'000'000;
constexpr long kMaxImageSide = 65536;

/// `value` (a string field `field` of `document`) as a path resolved against `base` (default: the
/// document's folder). Absolute paths and paths whose lexically normal form leaves `base` are
/// bad_input naming the document and the field, unless --allow-outside-paths was given.
std::filesystem::path resolve_document_path(const std::filesystem::path& document, std::string_view field,
                                            const std::string& value, std::optional<std::filesystem::path> base = {});
/// object[key] (a string) resolved as above; bad_input when missing or not a string.
std::filesystem::path path_field(const Json& object, std::string_view key, const std::filesystem::path& document,
                                 std::optional<std::filesystem::path> base = {});

/// A name that becomes part of a file name (sequence, space, part, region, camera): 1–128 of
/// [A-Za-z0-9_-.], not starting with '.'. bad_input naming the document and the field otherwise.
const std::string& check_name(const std::filesystem::path& document, std::string_view field, const std::string& name);
/// object[key] as a checked name.
std::string name_field(const Json& object, std::string_view key, const std::filesystem::path& document);

/// Throws unless `path` is a regular file (after symbolic links): io_error when it does not exist,
/// bad_input for a FIFO, device, socket or directory — those are never opened, so a reader can
/// neither block on a pipe nor read /dev/zero for ever. Returns its size in bytes.
std::uint64_t check_regular_file(const std::filesystem::path& path, std::optional<long> frame = std::nullopt);

/// Refuses (bad_input naming `file` and `what`) a request of `bytes` above the memory budget,
/// before anything is allocated.
void check_memory(const std::filesystem::path& file, const std::string& what, double bytes);

/// object[key] as an integer in [min, max] (core::integer_field); `fallback` when absent.
long integer_field_or(const Json& object, std::string_view key, const std::filesystem::path& document, long min,
                      long max, long fallback);

/// A finite number of magnitude ≤ max_abs; bad_input naming `file` and `what` otherwise.
double check_magnitude(const std::filesystem::path& file, const std::string& what, double value, double max_abs);
/// object[key] as a finite number in [min, max]; `fallback` when absent (bad_input if no fallback).
double number_field(const Json& object, std::string_view key, const std::filesystem::path& document, double min,
                    double max, std::optional<double> fallback = std::nullopt);

}  // namespace surfcap::core
