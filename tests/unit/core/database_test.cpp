#include <gtest/gtest.h>

#include <cmath>

#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/npy.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

core::AlignedDatabase small_database() {
  core::AlignedDatabase database;
  database.template_mesh = testing::make_sphere(5, 8, 0.3);
  for (const char* name : {"walk", "run"}) {
    core::AlignedSequence sequence;
    sequence.name = name;
    for (int t = 0; t < 4; ++t) {
      Eigen::MatrixXd frame = database.template_mesh.V * (1.0 + 0.05 * t);
      sequence.frames.push_back(frame);
      sequence.root_motion.push_back({0.1 * t, 0.9, -0.2 * t, 0.3 * t});
    }
    database.sequences.push_back(sequence);
  }
  database.root_sequence = "walk";
  database.root_frame = 2;
  return database;
}

TEST(Database, RoundTrip) {
  testing::TemporaryDirectory dir("database_round_trip");
  const core::AlignedDatabase database = small_database();
  core::write_database(dir.path(), database);
  const core::AlignedDatabase back = core::read_database(dir / "database.json");
  ASSERT_EQ(back.sequences.size(), 2u);
  EXPECT_EQ(back.root_sequence, "walk");
  EXPECT_EQ(back.root_frame, 2);
  EXPECT_EQ(back.template_mesh.F, database.template_mesh.F);
  EXPECT_EQ(back.sequences[1].name, "run");
  EXPECT_LT((back.sequences[1].frames[3] - database.sequences[1].frames[3]).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(back.sequences[0].root_motion[2].heading, 0.6, 1e-6);
  EXPECT_EQ(back.total_frames(), 8);
}

TEST(Database, WorldAndCentredAreInverse) {
  const Eigen::MatrixXd centred = testing::make_sphere(4, 6).V;
  const core::RootMotion root{1.0, 0.5, -2.0, 0.7};
  EXPECT_LT((core::to_centred(core::to_world(centred, root), root) - centred).cwiseAbs().maxCoeff(), 1e-12);
  // Heading is counter-clockwise about +y seen from above: +x turns towards -z.
  Eigen::MatrixXd x(1, 3);
  x << 1, 0, 0;
  const Eigen::MatrixXd turned = core::to_world(x, {0, 0, 0, M_PI / 2});
  EXPECT_NEAR(turned(0, 2), -1.0, 1e-12);
}

TEST(Database, FrameWithWrongVertexCountIsBadInput) {
  testing::TemporaryDirectory dir("database_bad_count");
  core::write_database(dir.path(), small_database());
  std::vector<float> wrong(4 * 10 * 3, 0.0f);
  core::write_npy(dir / "sequences" / "run.npy", wrong.data(), {4, 10, 3});
  try {
    core::read_database(dir / "database.json");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::bad_input);
    EXPECT_NE(std::string(e.what()).find("run.npy"), std::string::npos) << e.what();
  }
}

TEST(Database, NanFrameNamesTheFrame) {
  testing::TemporaryDirectory dir("database_nan");
  core::AlignedDatabase database = small_database();
  database.sequences[0].frames[3](5, 1) = std::nan("");
  core::write_database(dir.path(), database);
  try {
    core::read_database(dir / "database.json");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("walk.npy' (frame 3)"), std::string::npos) << e.what();
  }
}

TEST(Database, NewerFormatIsRefused) {
  testing::TemporaryDirectory dir("database_newer");
  core::write_database(dir.path(), small_database());
  core::Json document = core::read_json_file(dir / "database.json");
  document["format"] = "surfcap.database/9";
  core::write_json_file(dir / "database.json", document);
  EXPECT_THROW(core::read_database(dir / "database.json"), core::Error);
}

}  // namespace
}  // namespace surfcap
