// The compressed seed of the .glb fuzz corpus (tests/fuzz/corpus/glb/character_compressed.glb) is
// the fixture character.glb written in the compressed form by the current writer, so the fuzzer
// starts from the meshopt-coded, quantised and trajectory-coded arrays the exporter writes today.
// SURFCAP_WRITE_FUZZ_SEEDS=1 rewrites the seed when the format changes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "surfcap/asset/glb_character.hpp"
#include "surfcap/core/atomic_file.hpp"

namespace surfcap {
namespace {

TEST(FuzzCorpus, CompressedGlbSeedIsWhatTheWriterWrites) {
  const std::filesystem::path corpus = std::filesystem::path(SURFCAP_SOURCE_DIR) / "tests/fuzz/corpus/glb";
  const asset::Character character = asset::read_character_glb(corpus / "character.glb");
  asset::GlbSummary summary;
  const std::string bytes = asset::character_glb_bytes(character, {.generator = "surfcap fuzz seed"}, &summary);
  ASSERT_TRUE(summary.compressed);
  const auto seed = corpus / "character_compressed.glb";
  if (std::getenv("SURFCAP_WRITE_FUZZ_SEEDS") != nullptr) core::write_file_atomically(seed, bytes);
  ASSERT_TRUE(std::filesystem::exists(seed)) << "run with SURFCAP_WRITE_FUZZ_SEEDS=1 to write " << seed;
  EXPECT_EQ(core::read_file(seed), bytes) << seed << " is not what the writer writes today; rewrite it with "
                                          << "SURFCAP_WRITE_FUZZ_SEEDS=1";
  // It reads back to the character (compressed arrays within their steps; counts exact).
  const asset::Character back = asset::parse_character_glb(bytes, seed);
  EXPECT_EQ(back.template_mesh.V.rows(), character.template_mesh.V.rows());
  EXPECT_EQ(back.template_mesh.F, character.template_mesh.F);
}

}  // namespace
}  // namespace surfcap
