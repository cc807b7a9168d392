#pragma once
// Checked integers from JSON: nlohmann's get<int>() silently truncates a float and wraps a number
// too large for an int, so counts, indices and exponents read from files go through these.

#include <filesystem>
#include <limits>
#include <string_view>

#include "surfcap/core/json_document.hpp"

namespace surfcap::core {

/// `value` as an integer in [min, max]; bad_input (exit 3) naming `file` and `what` otherwise.
long checked_integer(const Json& value, std::string_view what, const std::filesystem::path& file,
                     long min = std::numeric_limits<int>::min(), long max = std::numeric_limits<int>::max());

/// The integer object[key] within [min, max]; bad_input when it is missing or otherwise.
long integer_field(const Json& object, std::string_view key, const std::filesystem::path& file,
                   long min = std::numeric_limits<int>::min(), long max = std::numeric_limits<int>::max());

}  // namespace surfcap::core
