// libFuzzer target: core::read_reconstruction (read_mesh + repair_mesh) on arbitrary bytes as PLY,
// OBJ or OFF (first byte picks). Whatever it returns must be a closed manifold with valid indices.
#include "fuzz_support.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_repair.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* extensions[] = {".obj", ".ply", ".off"};
  const auto path = surfcap::fuzz::scratch_file(data + 1, size - 1, extensions[data[0] % 3]);
  try {
    const surfcap::core::Mesh mesh = surfcap::core::read_reconstruction(path, 1);
    if (mesh.F.size() == 0 || mesh.F.minCoeff() < 0 || mesh.F.maxCoeff() >= mesh.vertex_count()) __builtin_trap();
    const surfcap::core::MeshCheck check = surfcap::core::check_mesh(mesh);
    if (!check.closed() || !check.manifold() || surfcap::core::count_pinch_vertices(mesh) > 0) __builtin_trap();
  } catch (const surfcap::core::Error&) {
  }
  return 0;
}
