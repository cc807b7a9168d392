// Every input of the .glb fuzz seed corpus (tests/fuzz/corpus/glb: valid seeds and the inputs
// that once crashed the reader) must either load or fail with a core::Error (exit 3 or 4).
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
