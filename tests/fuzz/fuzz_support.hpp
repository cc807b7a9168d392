#pragma once
// Shared by the libFuzzer targets: inputs go through a file, as in production.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace surfcap::fuzz {

/// A per-process scratch file with the given extension holding `data`.
inline std::filesystem::path scratch_file(const std::uint8_t* data, std::size_t size, const std::string& extension) {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path shm = "/dev/shm";
    auto base = std::filesystem::exists(shm) ? shm : std::filesystem::temp_directory_path();
    auto path = base / ("surfcap-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  const auto path = dir / ("input" + extension);
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace surfcap::fuzz
