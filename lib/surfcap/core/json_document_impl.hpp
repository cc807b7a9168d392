#pragma once
#include <limits>
#include <type_traits>

#include "surfcap/core/error.hpp"

namespace surfcap::core {

template <class T>
T get_field(const Json& object, std::string_view key, const std::filesystem::path& file) {
  const auto it = object.find(key);
  if (it == object.end()) throw bad_input(file, "missing field \"" + std::string(key) + "\"");
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>)
    check_integer_field(*it, key, file, static_cast<std::int64_t>(std::numeric_limits<T>::min()),
                        static_cast<std::uint64_t>(std::numeric_limits<T>::max()));
  try {
    return it->template get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(file, "field \"" + std::string(key) + "\" has the wrong type: " + e.what());
  }
}

}  // namespace surfcap::core
