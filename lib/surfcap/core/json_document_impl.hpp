#pragma once
#include <cstdint>
#include <limits>
#include <type_traits>

#include "surfcap/core/error.hpp"

namespace surfcap::core {

/// nlohmann's message without its "[json.exception.type_error.302] " prefix.
std::string json_error_text(const nlohmann::json::exception& error);

template <class Read>
auto read_document_fields(const std::filesystem::path& file, Read&& read) -> decltype(read()) {
  try {
    return read();
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(file, "a field is missing or has the wrong type: " + json_error_text(e));
  }
}

template <class T>
T get_field(const Json& object, std::string_view key, const std::filesystem::path& file) {
  const auto it = object.find(key);
  if (it == object.end()) throw bad_input(file, "missing field \"" + std::string(key) + "\"");
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    // get<int>() would truncate 2.5 and wrap (or, for a double beyond the type, be undefined).
    bool ok = false;
    if (it->is_number_unsigned())
      ok = it->template get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<T>::max());
    else if (it->is_number_integer())
      ok = it->template get<std::int64_t>() >= static_cast<std::int64_t>(std::numeric_limits<T>::min()) &&
           it->template get<std::int64_t>() <= static_cast<std::int64_t>(std::numeric_limits<T>::max());
    if (!ok)
      throw bad_input(file, "field \"" + std::string(key) + "\" must be an integer in [" +
                                std::to_string(std::numeric_limits<T>::min()) + ", " +
                                std::to_string(std::numeric_limits<T>::max()) + "]");
  }
  try {
    return it->template get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(file, "field \"" + std::string(key) + "\" has the wrong type: " + json_error_text(e));
  }
}

}  // namespace surfcap::core
