#include "surfcap/core/json_integer.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "surfcap/core/error.hpp"

namespace surfcap::core {

long checked_integer(const Json& value, std::string_view what, const std::filesystem::path& file, long min,
                     long max) {
  bool in_range = false;
  if (value.is_number_unsigned()) {
    const std::uint64_t v = value.get<std::uint64_t>();
    in_range = v <= static_cast<std::uint64_t>(std::max(max, 0L)) && (min <= 0 || v >= static_cast<std::uint64_t>(min));
  } else if (value.is_number_integer()) {
    const std::int64_t v = value.get<std::int64_t>();
    in_range = v >= min && v <= max;
  }
  if (!in_range)
    throw bad_input(file, std::string(what) + " must be an integer in [" + std::to_string(min) + ", " +
                              std::to_string(max) + "]");
  return static_cast<long>(value.get<std::int64_t>());
}

long integer_field(const Json& object, std::string_view key, const std::filesystem::path& file, long min, long max) {
  const auto it = object.find(key);
  if (it == object.end()) throw bad_input(file, "missing field \"" + std::string(key) + "\"");
  return checked_integer(*it, "field \"" + std::string(key) + "\"", file, min, max);
}

}  // namespace surfcap::core
