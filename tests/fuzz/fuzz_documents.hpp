#pragma once
// Shared by the document fuzz targets: a small real character (tests/fuzz/corpus/glb/character.glb,
// written by surfcap-export) and the files a document refers to, written once per process into the
// scratch folder beside the fuzzed document, so that a mutated document reaches every reader.
#include <filesystem>
#include <string>

#include "fuzz_support.hpp"
#include "surfcap/asset/glb_character.hpp"
#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::fuzz {

inline const std::filesystem::path& fixture_glb() {
  static const std::filesystem::path path = std::filesystem::path(SURFCAP_SOURCE_DIR) / "tests/fuzz/corpus/glb/character.glb";
  return path;
}

inline const asset::Character& fixture_character() {
  static const asset::Character character = asset::read_character_glb(fixture_glb());
  return character;
}

/// The scratch folder of this process (where scratch_file writes).
inline std::filesystem::path scratch_folder() {
  static const std::filesystem::path folder = [] {
    const std::uint8_t none = 0;
    return scratch_file(&none, 0, ".fixture").parent_path();
  }();
  return folder;
}

/// `data` written as `name` inside `folder` (created on first use).
inline std::filesystem::path document_file(const std::filesystem::path& folder, const std::string& name,
                                           const std::uint8_t* data, std::size_t size) {
  std::filesystem::create_directories(folder);
  const auto path = folder / name;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Runs `read` and accepts success or a surfcap error; anything else (another exception, a crash,
/// a sanitizer report) is a finding.
template <class Read>
void run_reader(Read&& read) {
  try {
    read();
  } catch (const core::Error&) {
  }
}

}  // namespace surfcap::fuzz
