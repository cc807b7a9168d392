#pragma once
// The aligned database (DESIGN §3.2, docs/formats.md): one template topology and, per sequence,
// the vertex positions of every frame (centred) plus the root motion. Written by surfcap-align
// (and by surfcap-synth as ground truth), read by every later stage; this module is its only
// reader and writer.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"

namespace surfcap::core {

/// Root motion of one frame: world = R_y(heading) · centred + (x, y, z). Heading in radians,
/// counter-clockwise about +y seen from above.
struct RootMotion {
  double x = 0, y = 0, z = 0, heading = 0;
};

struct AlignedSequence {
  std::string name;
  std::vector<Eigen::MatrixXd> frames;  ///< T frames of V×3 centred positions (metres)
  std::vector<RootMotion> root_motion;  ///< T entries
  int frame_count() const { return static_cast<int>(frames.size()); }
};

struct AlignedDatabase {
  Mesh template_mesh;  ///< connectivity (and colours/UVs) shared by every frame
  std::vector<AlignedSequence> sequences;
  std::string root_sequence;
  int root_frame = 0;
  double fps = 25.0;
  std::string units = "m";
  Json provenance = Json::object();  ///< tool, version, options, inputs

  int sequence_index(const std::string& name) const;  ///< -1 if absent
  long total_frames() const;
};

/// World-space positions of a centred frame.
Eigen::MatrixXd to_world(const Eigen::MatrixXd& centred, const RootMotion& root);
/// Centred positions of a world-space frame.
Eigen::MatrixXd to_centred(const Eigen::MatrixXd& world, const RootMotion& root);

/// Reads database.json and everything it references, checking shapes: every sequence must have
/// [T, V, 3] positions with the template's V and [T, 4] root motion; no NaN/Inf.
/// bad_input names the file and the frame at fault.
AlignedDatabase read_database(const std::filesystem::path& database_json);

/// Writes database.json, template.ply, sequences/<name>.npy and .root.npy into `directory`,
/// each atomically; database.json last, so a complete-looking database is complete.
void write_database(const std::filesystem::path& directory, const AlignedDatabase& database);

}  // namespace surfcap::core
