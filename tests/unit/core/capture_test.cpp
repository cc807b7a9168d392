#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

/// A minimal PNG signature + IHDR (enough for png_size; not a decodable image).
std::string png_header(int width, int height) {
  std::string bytes = "\x89PNG\r\n\x1a\n";
  bytes += std::string("\0\0\0\x0d", 4) + "IHDR";
  for (int value : {width, height})
    for (int shift : {24, 16, 8, 0}) bytes.push_back(static_cast<char>((value >> shift) & 0xff));
  return bytes + std::string(5, '\0');
}

core::Capture small_capture(const std::filesystem::path& folder) {
  core::Capture capture;
  capture.folder = folder;
  capture.name = "test";
  core::CaptureCamera camera;
  camera.name = "cam0";
  camera.width = 64;
  camera.height = 48;
  camera.K << 50, 0, 32, 0, 50, 24, 0, 0, 1;
  camera.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  camera.t << 0, -1, 3;
  capture.cameras.push_back(camera);
  capture.sequences.push_back({"walk", "walk/mesh/{frame:06d}.ply", "walk/images/{camera}/{frame:06d}.png", 3, 2});
  return capture;
}

void write_frames(const core::Capture& capture, int width = 64) {
  for (int frame = 3; frame < 5; ++frame) {
    core::write_mesh(capture.mesh_path(0, frame), testing::make_sphere(4, 6));
    testing::write_text(capture.image_path(0, frame, 0), png_header(width, 48));
  }
}

TEST(Capture, PatternExpansion) {
  EXPECT_EQ(core::expand_pattern("walk/mesh/{frame:06d}.ply", 12), "walk/mesh/000012.ply");
  EXPECT_EQ(core::expand_pattern("a/{camera}/{frame}.png", 7, "c3"), "a/c3/7.png");
  EXPECT_EQ(core::expand_pattern("{frame:3d}", 5), "005");
}

TEST(Capture, RoundTripAndFileChecks) {
  testing::TemporaryDirectory dir("capture_round_trip");
  const core::Capture capture = small_capture(dir.path());
  core::write_capture(capture);
  write_frames(capture);
  const core::Capture back = core::read_capture(dir.path());
  ASSERT_EQ(back.sequences.size(), 1u);
  EXPECT_EQ(back.total_frames(), 2);
  EXPECT_EQ(back.mesh_path(0, 4), dir / "walk/mesh/000004.ply");
  EXPECT_LT((back.cameras[0].R - capture.cameras[0].R).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NO_THROW(core::check_capture_files(back));
}

TEST(Capture, MissingFrameNamesFileAndFrame) {
  testing::TemporaryDirectory dir("capture_missing");
  const core::Capture capture = small_capture(dir.path());
  core::write_capture(capture);
  write_frames(capture);
  std::filesystem::remove(capture.mesh_path(0, 4));
  try {
    core::check_capture_files(core::read_capture(dir.path()));
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::bad_input);
    EXPECT_NE(std::string(e.what()).find("000004.ply' (frame 4)"), std::string::npos) << e.what();
  }
}

TEST(Capture, ImagesThatDoNotMatchTheCameraAreBadInput) {
  testing::TemporaryDirectory dir("capture_mismatch");
  const core::Capture capture = small_capture(dir.path());
  core::write_capture(capture);
  write_frames(capture, 80);
  try {
    core::check_capture_files(core::read_capture(dir.path()));
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("calibrated for 64×48"), std::string::npos) << e.what();
  }
}

TEST(Capture, BadCalibrationAndVersionsAreRefused) {
  testing::TemporaryDirectory dir("capture_bad");
  core::Capture capture = small_capture(dir.path());
  capture.cameras[0].R(0, 0) = 3;
  core::write_capture(capture);
  EXPECT_THROW(core::read_capture(dir.path()), core::Error);
  core::Json document = core::read_json_file(dir / "capture.json");
  document["format"] = "surfcap.capture/7";
  core::write_json_file(dir / "capture.json", document);
  try {
    core::read_capture(dir.path());
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("newer"), std::string::npos);
  }
}

}  // namespace
}  // namespace surfcap
