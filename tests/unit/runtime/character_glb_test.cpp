// The runtime plays a character read back from character.glb exactly as the one assembled in
// memory (uncompressed form), and within the rounding bound of references and displacement
// values from the compressed form (the asset module's reader and writer against the runtime's
// use of the model).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "surfcap/asset/glb_character.hpp"
#include "surfcap/runtime/controller.hpp"
#include "synthetic_space.hpp"
#include "test_support.hpp"

namespace {

using namespace surfcap;

void expect_same_playback(bool compress) {
  asset::Character character;
  character.name = "round_trip";
  character.template_mesh = surfcap::testing::make_sphere(6, 8, 0.3);
  const long V = character.template_mesh.V.rows();
  character.spaces.push_back(surfcap::testing::synthetic_space("walk", V, 12, true, 1));
  character.spaces.push_back(surfcap::testing::synthetic_space("jump", V, 16, false, 2, 0.0, 0.01));
  std::mt19937 random(3);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (auto [from, to] : {std::pair{0, 1}, std::pair{1, 0}}) {
    asset::CharacterTransition transition{character.spaces[from].name, character.spaces[to].name,
                                          3L * character.spaces[from].frames, 3L * character.spaces[to].frames, {}};
    for (long k = 0; k < transition.rows * transition.cols; ++k) transition.similarity.push_back(uniform(random));
    character.transitions.push_back(std::move(transition));
  }
  const surfcap::testing::TemporaryDirectory directory("runtime_glb");
  asset::GlbWriteOptions options;
  options.compress = compress;
  asset::write_character_glb(directory / "character.glb", character, options);
  const asset::Character read = asset::read_character_glb(directory / "character.glb");

  const core::Json json = {{"duration_s", 2.0},
                           {"start", {{"space", "walk"}, {"parameters", {{"u", 0.3}}}}},
                           {"timeline", {{{"time_s", 0.5}, {"space", "jump"}, {"parameters", {{"u", 0.8}}}}}}};
  const runtime::ControlScript original_script = runtime::parse_control_script(json, "c.json", character);
  const runtime::ControlScript read_script = runtime::parse_control_script(json, "c.json", read);
  runtime::Controller a(character, original_script), b(read, read_script);
  long frames = 0;
  while (!a.done()) {
    ASSERT_FALSE(b.done());
    a.step();
    b.step();
    ++frames;
    if (!compress) {
      ASSERT_EQ(a.world_positions(), b.world_positions()) << "frame " << frames;
      continue;
    }
    // ε = 5 mm: references within 2^-17 m, displacement values within 2^-14 m (docs/formats.md
    // "Trajectory coding"), blended with weights summing to 1; float32 sums on top.
    for (std::size_t i = 0; i < a.world_positions().size(); ++i)
      ASSERT_NEAR(a.world_positions()[i], b.world_positions()[i], std::ldexp(1.0, -17) + std::ldexp(1.0, -14) + 2e-6)
          << "frame " << frames;
  }
  EXPECT_TRUE(b.done());
  EXPECT_EQ(a.transitions().size(), b.transitions().size());
  EXPECT_GE(a.transitions().size(), 1u);
}

TEST(CharacterGlb, PlaysTheSameFramesAfterARoundTrip) { expect_same_playback(false); }

TEST(CharacterGlb, PlaysNearlyTheSameFramesFromTheCompressedForm) { expect_same_playback(true); }

}  // namespace
