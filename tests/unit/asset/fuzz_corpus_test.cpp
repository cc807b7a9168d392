// Every input of the .glb fuzz seed corpus (tests/fuzz/corpus/glb: valid seeds and the inputs
// that once crashed the reader) must either load or fail with a core::Error (exit 3 or 4).
// The seeds: character.glb = write_character_glb of testing::synthetic_character(make_sphere(3, 5,
// 0.5)) with 2 frames and a 2×2 PNG texture; character_float_colours.glb = the same without parts,
// texture, UVs, the 2-D space and transitions, colours 0.3 (float COLOR_0); animation.glb =
// write_animation_glb of 3 translated frames (no extension: refused as a character).
#include <gtest/gtest.h>

#include <algorithm>

#include "surfcap/asset/glb_character.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap {
namespace {

TEST(FuzzCorpus, GlbInputs) {
  std::vector<std::filesystem::path> inputs;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(SURFCAP_SOURCE_DIR) / "tests/fuzz/corpus/glb"))
    inputs.push_back(entry.path());
  std::sort(inputs.begin(), inputs.end());
  ASSERT_GE(inputs.size(), 3u);
  int loaded = 0;
  for (const auto& input : inputs) {
    try {
      asset::read_character_glb(input);
      ++loaded;
    } catch (const core::Error& e) {
      EXPECT_TRUE(e.code() == core::ExitCode::bad_input || e.code() == core::ExitCode::io) << input << ": " << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << input << " threw a non-surfcap exception: " << e.what();
    }
  }
  EXPECT_GE(loaded, 2);  // the two character seeds
}

}  // namespace
}  // namespace surfcap
