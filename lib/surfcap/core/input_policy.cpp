#include "surfcap/core/input_policy.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_integer.hpp"

namespace surfcap::core {
namespace {

std::string gigabytes(double bytes) {
  std::ostringstream text;
  text.precision(3);
  text << bytes / (1024.0 * 1024.0 * 1024.0) << " GiB";
  return text.str();
}

std::string number_text(double value) {
  std::ostringstream text;
  text.precision(6);
  text << value;
  return text.str();
}

}  // namespace

InputPolicy& input_policy() {
  static InputPolicy policy;
  return policy;
}

std::uint64_t memory_budget() {
  if (input_policy().max_memory_bytes > 0) return input_policy().max_memory_bytes;
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return std::uint64_t{4} << 30;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_size) / 2;
}

std::uint64_t parse_memory_size(const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw bad_arguments("--max-memory '" + text + "': expected bytes or a number with K, M, G or T");
  }
  const std::string unit = text.substr(used);
  double scale = 1;
  if (unit == "K" || unit == "k") scale = 1024.0;
  else if (unit == "M" || unit == "m") scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "g") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T" || unit == "t") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!unit.empty()) throw bad_arguments("--max-memory '" + text + "': unknown unit '" + unit + "' (K, M, G, T)");
  const double bytes = value * scale;
  if (!(bytes >= 0) || bytes > 1e18) throw bad_arguments("--max-memory '" + text + "' is out of range");
  return static_cast<std::uint64_t>(bytes);
}

std::filesystem::path resolve_document_path(const std::filesystem::path& document, std::string_view field,
                                            const std::string& value, std::optional<std::filesystem::path> base) {
  const std::filesystem::path folder = base ? *base : document.parent_path();
  auto refuse = [&](const std::string& why) -> Error {
    return bad_input(document, "field \"" + std::string(field) + "\": path '" + value + "' " + why +
                                   " (allow with --allow-outside-paths)");
  };
  if (value.empty()) throw bad_input(document, "field \"" + std::string(field) + "\": empty path");
  if (value.find('\0') != std::string::npos) throw bad_input(document, "field \"" + std::string(field) + "\": path holds a NUL byte");
  const std::filesystem::path relative(value);
  if (relative.is_absolute() || relative.has_root_name() || relative.has_root_directory()) {
    if (!input_policy().allow_outside_paths) throw refuse("is absolute; paths in a document are relative to its folder");
    return relative;
  }
  const std::filesystem::path normal = relative.lexically_normal();
  if (!normal.empty() && *normal.begin() == "..") {
    if (!input_policy().allow_outside_paths) throw refuse("leaves the folder '" + folder.string() + "'");
  }
  return folder / relative;
}

std::filesystem::path path_field(const Json& object, std::string_view key, const std::filesystem::path& document,
                                 std::optional<std::filesystem::path> base) {
  return resolve_document_path(document, key, get_field<std::string>(object, key, document), std::move(base));
}

const std::string& check_name(const std::filesystem::path& document, std::string_view field, const std::string& name) {
  bool ok = !name.empty() && name.size() <= 128 && name.front() != '.';
  for (const char c : name)
    ok = ok && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                c == '.');
  if (!ok)
    throw bad_input(document, "field \"" + std::string(field) + "\": name '" + name.substr(0, 160) +
                                  "' must be 1–128 letters, digits, '_', '-' or '.', not starting with '.'");
  return name;
}

std::string name_field(const Json& object, std::string_view key, const std::filesystem::path& document) {
  return check_name(document, key, get_field<std::string>(object, key, document));
}

std::uint64_t check_regular_file(const std::filesystem::path& path, std::optional<long> frame) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) {
    const int error_number = errno;
    if (error_number == ENOENT || error_number == ENOTDIR) throw io_error(path, "no such file");
    throw io_error(path, std::string("cannot open: ") + std::strerror(error_number));
  }
  if (S_ISREG(status.st_mode)) return static_cast<std::uint64_t>(status.st_size);
  const char* kind = S_ISDIR(status.st_mode)    ? "a directory"
                     : S_ISFIFO(status.st_mode) ? "a FIFO (named pipe)"
                     : S_ISCHR(status.st_mode)  ? "a character device"
                     : S_ISBLK(status.st_mode)  ? "a block device"
                     : S_ISSOCK(status.st_mode) ? "a socket"
                                                : "not a file";
  throw bad_input(path, std::string("is ") + kind + ", not a regular file", frame);
}

void check_memory(const std::filesystem::path& file, const std::string& what, double bytes) {
  const double budget = static_cast<double>(memory_budget());
  if (!(bytes <= budget))
    throw bad_input(file, what + " needs " + gigabytes(bytes) + ", more than the memory budget of " + gigabytes(budget) +
                              " (--max-memory)");
}

long integer_field_or(const Json& object, std::string_view key, const std::filesystem::path& document, long min,
                      long max, long fallback) {
  return object.is_object() && object.contains(key) ? integer_field(object, key, document, min, max) : fallback;
}

double check_magnitude(const std::filesystem::path& file, const std::string& what, double value, double max_abs) {
  if (!std::isfinite(value)) throw bad_input(file, what + " is NaN/Inf");
  if (std::abs(value) > max_abs)
    throw bad_input(file, what + " is " + number_text(value) + ", beyond the plausible magnitude " + number_text(max_abs));
  return value;
}

double number_field(const Json& object, std::string_view key, const std::filesystem::path& document, double min,
                    double max, std::optional<double> fallback) {
  const auto it = object.find(key);
  if (it == object.end()) {
    if (fallback) return *fallback;
    throw bad_input(document, "missing field \"" + std::string(key) + "\"");
  }
  if (!it->is_number()) throw bad_input(document, "field \"" + std::string(key) + "\" must be a number");
  const double value = it->get<double>();
  if (!(std::isfinite(value) && value >= min && value <= max))
    throw bad_input(document, "field \"" + std::string(key) + "\" is " + number_text(value) + ", expected a number in [" +
                                  number_text(min) + ", " + number_text(max) + "]");
  return value;
}

}  // namespace surfcap::core
