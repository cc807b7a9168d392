#pragma once
// Reading a parameter map back from JSON (blend.md space.json, formats.md .glb extension): one
// checked parser for both spellings.
#include <filesystem>

#include "surfcap/blend/parameter_map.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::blend {

/// The spellings of a parameter map's keys: space.json/graph.json (snake_case, residuals optional)
/// or the .glb's SURFCAP_motion_graph extension (camelCase, residuals required).
enum class ParameterMapKeys { space_json, gltf };

/// Parses a parameter map (ParameterMap::to_json, or its .glb form), checked throughout: degree an
/// integer in [0, 16]; one name, coefficient row and [min, max] range per axis (`dimensions`
/// axes, -1: as many as names); each monomial `dimensions` integer exponents >= 0 of total degree
/// <= degree. bad_input (exit 3) naming `file` otherwise.
ParameterMap read_parameter_map(const core::Json& json, const std::filesystem::path& file,
                                ParameterMapKeys keys = ParameterMapKeys::space_json, int dimensions = -1);

}  // namespace surfcap::blend
