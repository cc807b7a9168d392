#pragma once
// A motion space as `surfcap-precompute spaces` stored it (docs/blend.md): space.json and its
// arrays read back into memory. blend writes these files (motion_space.cpp), so blend also reads
// them; the transition stage, the character assembler and the runtime start from this struct.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "surfcap/blend/parameter_map.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::blend {

/// One source sequence of a motion space (corner order of docs/blend.md).
struct StoredSource {
  std::string sequence;
  int first = 0;          ///< first frame of the configured range in the database sequence
  int frames = 0;         ///< frames in that range
  double duration_s = 0;  ///< (frames − 1) / fps
};

struct StoredSpace {
  std::string name;
  bool cyclic = false;
  int frames = 0;      ///< T normalised frames
  int dimensions = 0;  ///< d; 2^d sources
  std::vector<StoredSource> sources;
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
  std::optional<ParameterMap> parameter_map;
  double tolerance_mm = 0;
  double max_error_mm = 0;

  int source_count() const { return 1 << dimensions; }
  long node_count() const { return static_cast<long>(node_coordinates.size()); }
  /// V, from the size of `references`.
  long vertex_count() const;
};

/// Parses a "parameter_map" object of space.json; bad_input names `file`.
ParameterMap parameter_map_from_json(const core::Json& json, const std::filesystem::path& file);

/// Reads <output>/spaces/<name>/space.json and every array it names (paths relative to
/// `output`), checking shapes against each other and, when `vertices` > 0, the vertex count.
StoredSpace read_stored_space(const std::filesystem::path& output, const std::string& name, long vertices = 0);

/// Same, from an entry of graph.json (or the "space" object of space.json); `file` names it in errors.
StoredSpace stored_space_from_entry(const core::Json& entry, const std::filesystem::path& output,
                                    const std::filesystem::path& file, long vertices = 0);

/// Checks the invariants of a space (sizes of every array, sorted breakpoints, CSR offsets
/// monotone and in range, vertex indices < V); bad_input naming `file`.
void check_stored_space(const StoredSpace& space, const std::filesystem::path& file);

}  // namespace surfcap::blend
