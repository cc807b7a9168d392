#pragma once
// Internal to asset/glb_*.cpp: reading EXT_meshopt_compression (the compressed form of
// character.glb and animation.glb, docs/formats.md) by decoding every compressed bufferView into
// an ordinary GLB that the rest of the reader checks as usual.
#include <filesystem>
#include <string>
#include <string_view>

namespace surfcap::asset::detail {

/// The GLB `glb` with every EXT_meshopt_compression bufferView decoded into the BIN chunk, the
/// data-less fallback buffer and the extension removed; empty when `glb` uses no such view.
/// bad_input (exit 3) naming `source` for a stream that does not decode, a mode or filter this
/// reader does not know, sizes that disagree or an implausible expansion ratio.
std::string decode_meshopt_glb(std::string_view glb, const std::filesystem::path& source);

}  // namespace surfcap::asset::detail
