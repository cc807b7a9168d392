#pragma once
// Internal to asset/glb_*.cpp: the vertex order of the compressed form. The meshopt codec
// predicts each element of a vertex stream from the one before, so the compressed form stores
// every per-vertex array in an order where consecutive vertices are neighbours on the surface
// (meshoptimizer's vertex cache + fetch order) and records the order; the reader restores the
// character's own (docs/formats.md "Vertex order").
#include <cstdint>
#include <filesystem>
#include <vector>

#include "surfcap/asset/character.hpp"

namespace surfcap::asset::detail {

/// order[i] = the character vertex stored as vertex i: a deterministic function of the faces.
std::vector<std::uint32_t> compression_vertex_order(const Eigen::MatrixXi& faces, long vertices);

/// The character with vertex i = `character`'s vertex order[i] in every per-vertex array (template,
/// frames, references, displacement rows — kept ascending by vertex —, part models) and every
/// vertex index (faces, part and region lists) renumbered.
Character reorder_vertices(const Character& character, const std::vector<std::uint32_t>& order);

/// The inverse order; bad_input naming `source` when `order` is not a permutation of 0..n−1.
std::vector<std::uint32_t> inverse_order(const std::vector<std::uint32_t>& order, long vertices,
                                         const std::filesystem::path& source);

}  // namespace surfcap::asset::detail
