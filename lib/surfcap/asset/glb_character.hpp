#pragma once
// The packaged character as one binary glTF 2.0 file (DESIGN §3.5, docs/formats.md
// "SURFCAP_motion_graph"): the template mesh with its colours or texture, every captured sequence
// as a morph-target animation any viewer plays, and everything the runtime needs in the vendor
// extension SURFCAP_motion_graph, its arrays in accessors of the same buffer.
#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "surfcap/asset/character.hpp"
#include "surfcap/core/mesh.hpp"

namespace surfcap::asset {

/// Version of SURFCAP_motion_graph this build writes and the newest it reads.
inline constexpr int motion_graph_extension_version = 4;

struct GlbWriteOptions {
  std::string generator;  ///< asset.generator; empty: "surfcap <version>"
  /// The compressed form (docs/formats.md): morph targets quantised (KHR_mesh_quantization) and
  /// heavy arrays meshopt-encoded (EXT_meshopt_compression), both then required by the file.
  /// false: plain float32 accessors every glTF 2.0 client reads, frames exact.
  bool compress = true;
};

/// What was written, for the export report.
struct GlbSummary {
  std::size_t file_bytes = 0;
  std::size_t json_bytes = 0;
  std::map<std::string, std::size_t> buffer_bytes;  ///< per content kind (template, morph_targets, ...)
  long morph_targets = 0;
  long animations = 0;
  long accessors = 0;
  bool compressed = false;  ///< the compressed form (GlbWriteOptions::compress)
};

/// The GLB bytes of `character`. Arrays are stored as float32 (doubles are rounded to float, as
/// in every surfcap .npy). Uncompressed, read(write(c)) == c exactly for float32-valued arrays —
/// every character assembled from build outputs; compressed, the morph targets, their normals and
/// the spaces' references are rounded (docs/formats.md gives the bounds) and
/// write(read(write(c))) == write(c). Same character → same bytes.
std::string character_glb_bytes(const Character& character, const GlbWriteOptions& options = {},
                                GlbSummary* summary = nullptr);
/// Writes character_glb_bytes atomically to `path`.
GlbSummary write_character_glb(const std::filesystem::path& path, const Character& character,
                               const GlbWriteOptions& options = {});

/// Reads a character .glb; bad_input (exit 3) naming the file for a truncated or corrupt file,
/// wrong accessor shapes, a missing extension or one from a newer version; io_error (4) if unreadable.
Character read_character_glb(const std::filesystem::path& path);
/// The same from bytes already in memory; `source` names them in errors.
Character parse_character_glb(std::string_view bytes, const std::filesystem::path& source);

/// An animation any glTF viewer plays (surfcap-play's output): the template mesh, one morph
/// target per frame (centred positions − template) and one animation `name` stepping through
/// them at `fps` (linear interpolation between frames) with the root motion on the node
/// (translation + rotation channels: world = R_y(heading)·centred + (x, y, z)). Written atomically.
GlbSummary write_animation_glb(const std::filesystem::path& path, const core::Mesh& template_mesh,
                               const std::vector<Eigen::MatrixXd>& centred_frames,
                               const std::vector<core::RootMotion>& root_motion, double fps, const std::string& name,
                               const GlbWriteOptions& options = {});

}  // namespace surfcap::asset
