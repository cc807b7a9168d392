#pragma once
// The binary glTF container (glTF 2.0 §4.4 "GLB File Format Specification"): a 12-byte header,
// a JSON chunk and an optional BIN chunk, each 4-byte aligned. No tinygltf here: the writer
// splices the SURFCAP_motion_graph extension into the JSON chunk, and the reader checks the
// container before any parser sees it.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace surfcap::asset {

/// Views into the bytes of a GLB file.
struct GlbChunks {
  std::string_view json;  ///< the JSON chunk without its trailing padding spaces
  std::string_view bin;   ///< the BIN chunk (padding included), empty when absent
};

/// Header + JSON chunk (padded with spaces) + BIN chunk (padded with zeros, omitted when empty).
/// internal_error if the result would exceed the 4 GiB a GLB can address.
std::string pack_glb(std::string_view json, std::span<const std::uint8_t> bin);

/// Checks magic "glTF", version 2, the declared length against the byte count, the chunk types,
/// lengths and alignment; bad_input (exit 3) naming `source` otherwise.
GlbChunks unpack_glb(std::string_view bytes, const std::filesystem::path& source);

}  // namespace surfcap::asset
