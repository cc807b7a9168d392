#include "surfcap/blend/stored_space.hpp"

#include <gtest/gtest.h>

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

}  // namespace
