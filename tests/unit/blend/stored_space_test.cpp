#include "surfcap/blend/stored_space.hpp"

#include <gtest/gtest.h>

#include "surfcap/blend/parameter_map_json.hpp"
#include "surfcap/core/error.hpp"
#include "synthetic_space.hpp"

namespace {

using namespace surfcap;

void expect_rejected(const blend::StoredSpace& space, const std::string& needle) {
  try {
    blend::check_stored_space(space, "space.json");
    FAIL() << "expected bad input: " << needle;
  } catch (const core::Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_NE(std::string(e.what()).find("space.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(StoredSpace, ChecksShapesAndTheSparseFields) {
  const blend::StoredSpace good = surfcap::testing::synthetic_space("walk", 20, 6, true, 1);
  EXPECT_NO_THROW(blend::check_stored_space(good, "space.json"));
  EXPECT_EQ(good.vertex_count(), 20);
  blend::StoredSpace bad = good;
  bad.displacement_offsets[3] = bad.displacement_offsets.back() + 5;
  expect_rejected(bad, "offsets");
  bad = good;
  bad.displacement_vertices[0] = 20;
  expect_rejected(bad, "out of range");
  bad = good;
  bad.breakpoints[0].front() = 0.1;
  expect_rejected(bad, "breakpoints");
  bad = good;
  bad.references.resize(bad.references.size() - 3);
  expect_rejected(bad, "references");
  bad = good;
  bad.node_coordinates.pop_back();
  expect_rejected(bad, "coordinates");
}

TEST(StoredSpace, ParameterMapsReadBackFromTheirJson) {
  const blend::StoredSpace space = surfcap::testing::synthetic_space("walk", 4, 3, true, 1);
  const blend::ParameterMap map = blend::parameter_map_from_json(space.parameter_map->to_json(), "space.json");
  EXPECT_EQ(map.monomials, space.parameter_map->monomials);
  EXPECT_EQ(map.weights_for({0.25}), space.parameter_map->weights_for({0.25}));
  core::Json broken = space.parameter_map->to_json();
  broken["coefficients"] = core::Json::array();
  EXPECT_THROW(blend::parameter_map_from_json(broken, "space.json"), core::Error);
}

// Exponents and the degree are integers in range, whichever file they come from: a negative
// exponent made p⁰ = 0 an infinity, a float or a huge number was truncated silently by get<int>().
TEST(StoredSpace, ParameterMapExponentsAreCheckedIntegers) {
  const blend::StoredSpace space = surfcap::testing::synthetic_space("walk", 4, 3, true, 1);
  const core::Json good = space.parameter_map->to_json();
  ASSERT_GE(good["degree"].get<int>(), 1);
  const auto rejected = [&](const core::Json& json, const std::string& needle) {
    try {
      blend::parameter_map_from_json(json, "space.json");
      ADD_FAILURE() << "accepted " << json["monomials"].dump() << " (degree " << json["degree"].dump() << ")";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.exit_code(), 3) << e.what();
      EXPECT_NE(std::string(e.what()).find("space.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  for (const core::Json exponent : {core::Json(-1), core::Json(1.5), core::Json(4294967297LL), core::Json("1"),
                                    core::Json(good["degree"].get<int>() + 1)}) {
    core::Json bad = good;
    bad["monomials"][1][0] = exponent;
    rejected(bad, "exponent");
  }
  core::Json bad = good;
  bad["monomials"][1].push_back(0);
  rejected(bad, "exponents");
  for (const core::Json degree : {core::Json(-1), core::Json(2.5), core::Json(1LL << 40)}) {
    bad = good;
    bad["degree"] = degree;
    rejected(bad, "degree");
  }
  // The .glb spelling goes through the same parser.
  core::Json gltf = good;
  gltf["parameterRange"] = gltf["parameter_range"];
  gltf["residualRms"] = gltf["residual_rms"];
  gltf["residualMax"] = gltf["residual_max"];
  EXPECT_EQ(blend::read_parameter_map(gltf, "c.glb", blend::ParameterMapKeys::gltf, 1).monomials,
            space.parameter_map->monomials);
  EXPECT_THROW(blend::read_parameter_map(gltf, "c.glb", blend::ParameterMapKeys::gltf, 2), core::Error);
  gltf["monomials"][1][0] = -1;
  EXPECT_THROW(blend::read_parameter_map(gltf, "c.glb", blend::ParameterMapKeys::gltf, 1), core::Error);
}

}  // namespace
