#pragma once
#include "surfcap/core/error.hpp"

namespace surfcap::core {

template <class T>
T get_field(const Json& object, std::string_view key, const std::filesystem::path& file) {
  const auto it = object.find(key);
  if (it == object.end()) throw bad_input(file, "missing field \"" + std::string(key) + "\"");
  try {
    return it->template get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(file, "field \"" + std::string(key) + "\" has the wrong type: " + e.what());
  }
}

}  // namespace surfcap::core
