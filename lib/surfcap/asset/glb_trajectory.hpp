#pragma once
// Internal to asset/glb_extension_*.cpp: the compressed form's fixed-point trajectory coding of a
// space's references and displacement fields (docs/formats.md "Trajectory coding"). Values become
// integers q = round(value / 2^exponent), stored frame by frame as zigzag-coded differences from
// the same vertex's previous (stored) frame: the meshopt vertex codec predicts every element from
// the one before, and the frame differences of neighbouring vertices differ little.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "surfcap/asset/character.hpp"

namespace surfcap::asset::detail {

/// 2^exponent m, the fixed-point steps of a space of tolerance ε: the largest powers of two
/// ≤ ε/256 for references (the exact non-linear blend amplifies their rounding: ε = 5 mm gives
/// 2^-16 m ≈ 15 µm) and ≤ ε/32 for displacement values (added after the blend: 2^-13 m ≈ 0.12 mm),
/// within [2^-24, 2^-8] m.
int reference_step_exponent(double tolerance_mm);
int displacement_step_exponent(double tolerance_mm);

/// References [N][T][V][3] → codes in the same layout, each the difference from the vertex's
/// previous frame (frame 0: from 0); false (nothing written) when a value needs more than 24 bits.
bool encode_references(const std::vector<float>& references, long sources, long frames, long vertices, int exponent,
                       std::vector<std::uint32_t>& codes);
/// Their inverse; bad_input naming `source` when a code leaves the 24-bit range.
std::vector<float> decode_references(const std::vector<std::uint32_t>& codes, long sources, long frames,
                                     long vertices, int exponent, const std::filesystem::path& source,
                                     const std::string& what);

/// A space's displacement fields: `masks` [R][V][W] (W = ⌈T/32⌉ words; bit t % 32 of word t / 32
/// set when vertex v is stored at frame t of node r) and `values` [K][3] in row order (node,
/// frame, then vertex ascending), each the difference from the vertex's previous stored frame at
/// that node (from 0 at the first).
struct DisplacementCodes {
  std::vector<std::uint32_t> masks;
  std::vector<std::uint32_t> values;
};
/// false when the fields cannot be coded (a vertex stored twice in a row, a value beyond 24 bits).
bool encode_displacements(const CharacterSpace& space, long vertices, int exponent, DisplacementCodes& codes);
/// Fills the space's CSR arrays (rows ordered by vertex); bad_input naming `source` for masks
/// with bits beyond T, a value count differing from the masks' or codes beyond 24 bits.
void decode_displacements(const DisplacementCodes& codes, long vertices, int exponent, CharacterSpace& space,
                          const std::filesystem::path& source, const std::string& what);

/// A part model's basis (3n rows: x, y, z of each part vertex; k columns) in the compressed form:
/// column by column, each part vertex as int16 (x, y, z, 0) codes q = round(b / 2^e_c) with e_c
/// the smallest exponent keeping the column's codes within ±32767 (16 significant bits of the
/// column's largest value). Writing what this decodes gives the same codes.
struct QuantisedBasis {
  std::vector<std::int16_t> codes;  ///< k·n·4
  std::vector<int> exponents;       ///< k
};
QuantisedBasis quantise_basis(const Eigen::MatrixXd& basis);
/// Its inverse for `rows` = 3n rows; bad_input naming `source` for sizes that disagree or
/// exponents outside [−64, 8].
Eigen::MatrixXd dequantise_basis(const std::vector<std::int16_t>& codes, const std::vector<int>& exponents, long rows,
                                 const std::filesystem::path& source, const std::string& what);

}  // namespace surfcap::asset::detail
