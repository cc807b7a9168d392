// libFuzzer target: core::read_mesh on arbitrary bytes as PLY, OBJ or OFF (first byte picks).
#include "fuzz_support.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* extensions[] = {".ply", ".obj", ".off"};
  const auto path = surfcap::fuzz::scratch_file(data + 1, size - 1, extensions[data[0] % 3]);
  try {
    surfcap::core::MeshRequirements lenient;
    lenient.allow_non_manifold = (data[0] & 4) != 0;
    lenient.allow_zero_area_faces = (data[0] & 8) != 0;
    const surfcap::core::Mesh mesh = surfcap::core::read_mesh(path, lenient, 1);
    // What validation accepted must be usable: indices in range, coordinates finite.
    if (mesh.F.size() > 0 && (mesh.F.minCoeff() < 0 || mesh.F.maxCoeff() >= mesh.vertex_count())) __builtin_trap();
    if (!mesh.V.allFinite()) __builtin_trap();
  } catch (const surfcap::core::Error&) {
  }
  return 0;
}
