// The compressed form's fixed-point trajectory coding of references and displacement fields:
// decode(encode(x)) is x rounded to the step (x itself on the grid), rows come back ordered by
// vertex with the same entries, uncodable input is left to the plain form, and codes that do not
// describe a space are refused naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "surfcap/asset/glb_trajectory.hpp"
#include "surfcap/core/npy.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using asset::detail::DisplacementCodes;

TEST(TrajectoryCoding, StepsFollowTheTolerance) {
  EXPECT_EQ(asset::detail::reference_step_exponent(5), -16);     // 5 mm / 256 ≥ 2^-16 m
  EXPECT_EQ(asset::detail::displacement_step_exponent(5), -13);  // 5 mm / 32 ≥ 2^-13 m
  EXPECT_EQ(asset::detail::displacement_step_exponent(0), -24);
  EXPECT_EQ(asset::detail::displacement_step_exponent(1e6), -8);
}

TEST(TrajectoryCoding, ReferencesRoundToTheStepAndGridValuesReadBackExactly) {
  const long sources = 2, frames = 7, vertices = 5;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.4f);
  std::vector<float> references(sources * frames * vertices * 3);
  for (float& x : references) x = noise(rng);
  std::vector<std::uint32_t> codes;
  ASSERT_TRUE(asset::detail::encode_references(references, sources, frames, vertices, -13, codes));
  const auto decoded = asset::detail::decode_references(codes, sources, frames, vertices, -13, "r.glb", "refs");
  ASSERT_EQ(decoded.size(), references.size());
  for (std::size_t i = 0; i < decoded.size(); ++i) {
    EXPECT_LE(std::abs(decoded[i] - references[i]), std::ldexp(1.0, -14));
    EXPECT_EQ(decoded[i], std::ldexp(std::nearbyint(std::ldexp(references[i], 13)), -13));
  }
  std::vector<std::uint32_t> again;
  ASSERT_TRUE(asset::detail::encode_references(decoded, sources, frames, vertices, -13, again));
  EXPECT_EQ(again, codes);
  // Codes are frame differences: a still vertex codes 0 after its first frame.
  std::vector<float> still(frames * vertices * 3, 0.25f);
  ASSERT_TRUE(asset::detail::encode_references(still, 1, frames, vertices, -13, codes));
  EXPECT_EQ(codes[0], 2u * 2048);  // zigzag(0.25 / 2^-13)
  for (std::size_t i = vertices * 3; i < codes.size(); ++i) EXPECT_EQ(codes[i], 0u);
  // Beyond 24 bits at the step: left to the plain form.
  still[4] = 3000.0f;
  EXPECT_FALSE(asset::detail::encode_references(still, 1, frames, vertices, -13, codes));
  // A trajectory leaving the 24-bit range is refused.
  std::vector<std::uint32_t> runaway(frames * vertices * 3, 0);
  for (long t = 0; t < frames; ++t) runaway[t * vertices * 3] = 2u * (1u << 22);
  testing::expect_bad_input([&] { asset::detail::decode_references(runaway, 1, frames, vertices, -13, "r.glb", "refs"); },
                            "r.glb");
}

/// A space of `nodes` 1-D grid nodes, T frames, V vertices, each row storing a random subset of
/// vertices in a shuffled order.
asset::CharacterSpace space_with_fields(long nodes, int frames, long vertices) {
  asset::CharacterSpace s;
  s.name = "s";
  s.frames = frames;
  s.dimensions = 1;
  for (long r = 0; r < nodes; ++r) s.node_coordinates.push_back({r / double(nodes - 1)});
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  s.displacement_offsets.push_back(0);
  for (long row = 0; row < nodes * frames; ++row) {
    std::vector<int> chosen;
    for (int v = 0; v < vertices; ++v)
      if (rng() % 3 == 0) chosen.push_back(v);
    std::shuffle(chosen.begin(), chosen.end(), rng);
    for (int v : chosen) {
      s.displacement_vertices.push_back(v);
      for (int c = 0; c < 3; ++c) s.displacement_values.push_back(core::float_to_half(noise(rng)));
    }
    s.displacement_offsets.push_back(static_cast<std::int64_t>(s.displacement_vertices.size()));
  }
  return s;
}

/// Row → vertex → the three float16 values.
std::map<std::pair<long, int>, std::tuple<float, float, float>> entries(const asset::CharacterSpace& s) {
  std::map<std::pair<long, int>, std::tuple<float, float, float>> out;
  for (long row = 0; row + 1 < static_cast<long>(s.displacement_offsets.size()); ++row)
    for (auto k = s.displacement_offsets[row]; k < s.displacement_offsets[row + 1]; ++k)
      out[{row, s.displacement_vertices[k]}] = {core::half_to_float(s.displacement_values[3 * k]),
                                                core::half_to_float(s.displacement_values[3 * k + 1]),
                                                core::half_to_float(s.displacement_values[3 * k + 2])};
  return out;
}

TEST(TrajectoryCoding, DisplacementFieldsKeepTheirEntriesWithinHalfAStep) {
  const long vertices = 23;
  const asset::CharacterSpace space = space_with_fields(3, 40, vertices);  // 40 frames: two mask words
  DisplacementCodes codes;
  ASSERT_TRUE(asset::detail::encode_displacements(space, vertices, -13, codes));
  EXPECT_EQ(codes.masks.size(), 3u * vertices * 2);
  EXPECT_EQ(codes.values.size(), space.displacement_values.size());
  asset::CharacterSpace read = space;
  asset::detail::decode_displacements(codes, vertices, -13, read, "d.glb", "fields");
  const auto before = entries(space), after = entries(read);
  ASSERT_EQ(before.size(), after.size());
  for (auto a = before.begin(), b = after.begin(); a != before.end(); ++a, ++b) {
    ASSERT_EQ(a->first, b->first);
    for (const auto& [x, y] : {std::pair{std::get<0>(a->second), std::get<0>(b->second)},
                               std::pair{std::get<1>(a->second), std::get<1>(b->second)},
                               std::pair{std::get<2>(a->second), std::get<2>(b->second)}})
      EXPECT_LE(std::abs(x - y), std::ldexp(1.0, -14));
  }
  for (long row = 0; row < 3 * 40; ++row)  // rows ordered by vertex
    EXPECT_TRUE(std::is_sorted(read.displacement_vertices.begin() + read.displacement_offsets[row],
                               read.displacement_vertices.begin() + read.displacement_offsets[row + 1]));
  // Coding what was read gives the same codes (idempotent rounding).
  DisplacementCodes again;
  ASSERT_TRUE(asset::detail::encode_displacements(read, vertices, -13, again));
  EXPECT_EQ(again.masks, codes.masks);
  EXPECT_EQ(again.values, codes.values);

  // A vertex stored twice in a row cannot be coded.
  asset::CharacterSpace twice = space;
  twice.displacement_vertices[1] = twice.displacement_vertices[0];
  if (space.displacement_offsets[1] >= 2) EXPECT_FALSE(asset::detail::encode_displacements(twice, vertices, -13, again));

  // Refused: a frame beyond T, values disagreeing with the masks, masks of the wrong size.
  DisplacementCodes bad = codes;
  bad.masks[1] |= 1u << 9;  // frame 41 of node 0, vertex 0
  testing::expect_bad_input([&] { asset::detail::decode_displacements(bad, vertices, -13, read, "d.glb", "f"); }, "beyond T");
  bad = codes;
  bad.values.resize(bad.values.size() - 3);
  testing::expect_bad_input([&] { asset::detail::decode_displacements(bad, vertices, -13, read, "d.glb", "f"); }, "d.glb");
  bad = codes;
  bad.masks.pop_back();
  testing::expect_bad_input([&] { asset::detail::decode_displacements(bad, vertices, -13, read, "d.glb", "f"); }, "d.glb");
}

}  // namespace
}  // namespace surfcap
