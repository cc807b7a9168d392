#pragma once
// Internal to asset/glb_*.cpp: the SURFCAP_motion_graph extension object (docs/formats.md) —
// spaces, transitions and part models — written into and read from a glTF model's accessors.
#include <string>
#include <string_view>

#include "surfcap/asset/character.hpp"
#include "surfcap/asset/glb_model.hpp"
#include "surfcap/core/json_integer.hpp"

namespace surfcap::asset::detail {

inline constexpr const char* motion_graph_extension = "SURFCAP_motion_graph";
/// The integer JSON number object[key] within [min, max]; bad_input naming the file otherwise.
using core::integer_field;

/// "spaces", "transitions" and "parts" of the extension, their arrays added to `builder`.
/// internal_error when an array's size disagrees with the shape its metadata implies.
core::Json spaces_json(GlbBuilder& builder, const Character& character);
core::Json transitions_json(GlbBuilder& builder, const Character& character);
core::Json parts_json(GlbBuilder& builder, const Character& character);

/// Their inverses; bad_input naming the file for wrong shapes or inconsistent metadata.
/// `character` already holds the template, fps and sequences.
void read_spaces(const core::Json& extension, const GlbAccessors& accessors, Character& character);
void read_transitions(const core::Json& extension, const GlbAccessors& accessors, Character& character);
void read_parts(const core::Json& extension, const GlbAccessors& accessors, Character& character);

}  // namespace surfcap::asset::detail
