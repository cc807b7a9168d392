#pragma once
// Structural checks of a PLY or OFF file before OpenMesh parses it. OpenMesh's stream parsers
// read uninitialised values on malformed input (a "nan" token in an ASCII PLY can make it
// allocate gigabytes), so what reaches them must be well formed.

#include <filesystem>
#include <optional>
#include <string>

namespace surfcap::core {

struct MeshFileCounts {
  long vertices = -1;  ///< as declared by the header; -1 when the format has no header (OBJ)
  long faces = -1;
};

/// For .ply and .off: parses the header and walks every element record (ASCII tokens or binary
/// bytes), checking that numbers are finite, list lengths sane and nothing is truncated.
/// bad_input names the file, the frame and the element/line at fault. For .obj: vertex lines
/// must hold finite numbers and colour values in [0, 1].
MeshFileCounts precheck_mesh_file(const std::filesystem::path& path, const std::string& extension,
                                  std::optional<long> frame);

}  // namespace surfcap::core
