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
#include "surfcap/core/database.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/learn/part_model.hpp"

namespace surfcap::asset {

/// One source sequence of a motion space (corner order of docs/blend.md).
struct SpaceSource {
  std::string sequence;
  int first = 0;          ///< first frame of the configured range in the database sequence
  int frames = 0;         ///< frames in that range
  double duration_s = 0;  ///< (frames − 1) / fps
};

/// A parametric motion space as surfcap-precompute spaces wrote it (docs/blend.md).
struct CharacterSpace {
  std::string name;
  bool cyclic = false;
  int frames = 0;      ///< T normalised frames
  int dimensions = 0;  ///< d; 2^d sources
  std::vector<SpaceSource> sources;
  std::vector<std::string> parameter_names;     ///< d names, or empty
  std::vector<std::string> parameter_measures;  ///< d measures (root_speed, ...), or empty
  std::vector<std::vector<double>> breakpoints;       ///< [d][*] sorted, incl. 0 and 1
  std::vector<std::vector<double>> node_coordinates;  ///< [R][d] grid nodes, axis 0 fastest, corners included
  std::vector<float> references;   ///< [N][T][V][3] time-warped centred source positions (metres)
  std::vector<float> root_motion;  ///< [N][T][4] x, y, z, heading
  std::vector<float> time_warp;    ///< [N][T] fractional source frame within the range
  std::vector<std::int64_t> displacement_offsets;   ///< [R·T + 1] CSR offsets, row = node·T + t
  std::vector<std::int32_t> displacement_vertices;  ///< [K]
  std::vector<std::uint16_t> displacement_values;   ///< [K][3] IEEE 754 half-precision bits (metres)
  double displacement_threshold_m = 0;
  std::optional<blend::ParameterMap> parameter_map;
  double tolerance_mm = 0;
  double max_error_mm = 0;

  int source_count() const { return 1 << dimensions; }
  long node_count() const { return static_cast<long>(node_coordinates.size()); }
};

/// Transition similarity between two connected spaces (casas2013 §3.2): s = 1 − d / max d over
/// every frame of every grid node (reference) of `from` × every frame of every node of `to`.
struct CharacterTransition {
  std::string from;
  std::string to;
  long rows = 0;  ///< R_from · T_from, row = node · T_from + t
  long cols = 0;  ///< R_to · T_to
  std::vector<float> similarity;  ///< row-major [rows][cols], in [0, 1]
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
