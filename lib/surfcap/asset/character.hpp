#pragma once
// The packaged character (DESIGN §3.5): everything surfcap-export puts into character.glb and
// the runtime plays. One in-memory model shared by the build-folder loader (assemble_character),
// the .glb writer/reader (asset/glb_*) and runtime/.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "surfcap/blend/parameter_map.hpp"
#include "surfcap/blend/stored_space.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/learn/part_model.hpp"

namespace surfcap::asset {

/// One source sequence of a motion space (corner order of docs/blend.md).
using SpaceSource = blend::StoredSource;

/// A parametric motion space as surfcap-precompute spaces wrote it (docs/blend.md): the fields
/// name, cyclic, frames, dimensions, sources, parameter_names/measures, breakpoints,
/// node_coordinates, references, root_motion, time_warp, displacement_{offsets,vertices,values,
/// threshold_m}, parameter_map, tolerance_mm, max_error_mm (blend/stored_space.hpp reads them).
using CharacterSpace = blend::StoredSpace;

/// Transition similarity between two connected spaces (casas2013 §3.2): s = 1 − d / max d over
/// every frame of every grid node (reference) of `from` × every frame of every node of `to`.
struct CharacterTransition {
  std::string from;
  std::string to;
  long rows = 0;  ///< R_from · T_from, row = node · T_from + t
  long cols = 0;  ///< R_to · T_to
  std::vector<float> similarity;  ///< row-major [rows][cols], in [0, 1]

  float at(long row, long col) const { return similarity[static_cast<std::size_t>(row * cols + col)]; }
};

struct Character {
  std::string name;
  core::Mesh template_mesh;  ///< the one topology, with its colours / UVs
  std::vector<std::uint8_t> texture_png;  ///< optional base-colour texture (PNG bytes) mapped by template_mesh.uvs
  double fps = 25.0;
  std::string units = "m";
  std::vector<core::AlignedSequence> sequences;  ///< captured sequences (glTF morph-target animations)
  std::vector<CharacterSpace> spaces;
  std::vector<CharacterTransition> transitions;
  std::optional<learn::LearntModel> parts;  ///< part bases + hierarchy, when learnt
  core::Json provenance = core::Json::object();

  long vertex_count() const { return template_mesh.V.rows(); }
  int space_index(const std::string& space) const;  ///< -1 if absent
  /// The transition from → to, or nullptr.
  const CharacterTransition* find_transition(const std::string& from, const std::string& to) const;
};

/// The build outputs a character is assembled from.
struct CharacterInputs {
  std::filesystem::path database;  ///< database.json (aligned database)
  std::filesystem::path graph;     ///< graph.json of surfcap-precompute (spaces + transitions beside it)
  std::filesystem::path parts;     ///< parts.json of surfcap-learn; empty: no part models
  std::string name = "character";
};

/// Reads and cross-checks every input (same vertex count and template everywhere, every space's
/// sequences in the database, every declared transition present); bad_input names the file.
Character assemble_character(const CharacterInputs& inputs);

}  // namespace surfcap::asset
