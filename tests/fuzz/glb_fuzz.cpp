// libFuzzer target: asset::read_character_glb on arbitrary bytes. What the reader accepts must be
// a usable character: every frame, reference and index within the template's vertex count.
#include <vector>

#include "fuzz_support.hpp"
#include "surfcap/asset/glb_character.hpp"
#include "surfcap/core/error.hpp"

namespace {

void check(const surfcap::asset::Character& c) {
  const long v = c.vertex_count();
  if (c.template_mesh.F.size() > 0 && (c.template_mesh.F.minCoeff() < 0 || c.template_mesh.F.maxCoeff() >= v)) __builtin_trap();
  for (const auto& s : c.sequences) {
    if (s.root_motion.size() != s.frames.size()) __builtin_trap();
    for (const auto& frame : s.frames)
      if (frame.rows() != v || frame.cols() != 3) __builtin_trap();
  }
  for (const auto& s : c.spaces) {
    const std::size_t n = s.source_count(), t = s.frames;
    if (s.references.size() != n * t * v * 3 || s.root_motion.size() != n * t * 4 || s.time_warp.size() != n * t) __builtin_trap();
    if (s.displacement_offsets.size() != static_cast<std::size_t>(s.node_count()) * t + 1) __builtin_trap();
    if (s.displacement_offsets.back() != static_cast<long>(s.displacement_vertices.size())) __builtin_trap();
    if (s.displacement_values.size() != 3 * s.displacement_vertices.size()) __builtin_trap();
    for (int i : s.displacement_vertices)
      if (i < 0 || i >= v) __builtin_trap();
  }
  for (const auto& t : c.transitions)
    if (t.similarity.size() != static_cast<std::size_t>(t.rows * t.cols)) __builtin_trap();
  if (c.parts)
    for (const auto& p : c.parts->parts)
      if (p.mean.size() != 3 * static_cast<long>(p.part.vertices.size()) || p.basis.rows() != p.mean.size()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The header's total length is patched to the input size, so that mutations that grow or shrink
  // the input reach the chunks and the JSON instead of stopping at the length check (which the
  // unit tests cover).
  std::vector<std::uint8_t> bytes(data, data + size);
  if (size >= 12)
    for (int k = 0; k < 4; ++k) bytes[8 + k] = static_cast<std::uint8_t>((size >> (8 * k)) & 0xFF);
  const auto path = surfcap::fuzz::scratch_file(bytes.data(), bytes.size(), ".glb");
  try {
    check(surfcap::asset::read_character_glb(path));
  } catch (const surfcap::core::Error&) {
  }
  return 0;
}
