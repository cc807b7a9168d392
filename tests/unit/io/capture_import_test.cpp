#include <gtest/gtest.h>

#include <string>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/io/capture_import.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/render/png.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using testing::expect_bad_input;

/// walk/mesh/000000..000002.ply with images of two cameras, run/run_8..run_11.obj (flat, unpadded),
/// a calibration/ folder that is not a sequence, and the two cameras in rig.json.
void make_studio_folder(const std::filesystem::path& folder) {
  const core::Mesh sphere = testing::make_sphere(6, 8, 0.5);
  std::filesystem::create_directories(folder / "walk" / "mesh");
  std::filesystem::create_directories(folder / "run");
  std::filesystem::create_directories(folder / "calibration");
  for (int frame = 0; frame < 3; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.ply", frame);
    core::write_mesh(folder / "walk" / "mesh" / name, sphere);
  }
  for (int frame = 8; frame < 12; ++frame)
    core::write_mesh(folder / "run" / ("run_" + std::to_string(frame) + ".obj"), sphere);
  const auto cameras = render::ring_cameras(2, 3.0, 1.5, Eigen::Vector3d(0, 1, 0), 50, 40, 30);
  render::write_cameras(folder / "calibration" / "rig.json", cameras);
  for (const auto& camera : cameras) {
    std::filesystem::create_directories(folder / "walk" / "images" / camera.name);
    for (int frame = 0; frame < 3; ++frame)
      render::write_png(folder / "walk" / "images" / camera.name / ("img" + std::to_string(frame) + ".png"),
                        render::Image(40, 30));
  }
}

TEST(CaptureImport, NumberedFoldersBecomeSequences) {
  const testing::TemporaryDirectory dir("capture_import");
  const auto folder = dir / "studio";
  make_studio_folder(folder);
  io::CaptureImportOptions options;
  options.folder = folder;
  options.calibration = folder / "calibration" / "rig.json";
  options.fps = 30;
  core::Capture capture = io::import_capture(options);
  EXPECT_EQ(capture.name, "studio");
  ASSERT_EQ(capture.sequences.size(), 2u);
  EXPECT_EQ(capture.sequences[0].name, "run");
  EXPECT_EQ(capture.sequences[0].frames, "run/run_{frame}.obj");
  EXPECT_EQ(capture.sequences[0].first, 8);
  EXPECT_EQ(capture.sequences[0].count, 4);
  EXPECT_TRUE(capture.sequences[0].images.empty());
  EXPECT_EQ(capture.sequences[1].name, "walk");
  EXPECT_EQ(capture.sequences[1].frames, "walk/mesh/{frame:06d}.ply");
  EXPECT_EQ(capture.sequences[1].images, "walk/images/{camera}/img{frame}.png");
  EXPECT_EQ(capture.sequences[1].count, 3);
  ASSERT_EQ(capture.cameras.size(), 2u);
  // Written and read back, it is a capture every stage accepts.
  core::write_capture(capture);
  const core::Capture reread = core::read_capture(folder);
  EXPECT_EQ(reread.total_frames(), 7);
  EXPECT_DOUBLE_EQ(reread.fps, 30);
  EXPECT_EQ(reread.mesh_path(1, 2), folder / "walk/mesh/000002.ply");
  EXPECT_EQ(reread.image_path(1, 1, 0), folder / "walk/images/cam00/img1.png");
  core::check_capture_files(reread);
}

TEST(CaptureImport, GapsUnknownCamerasAndMixedSeriesAreBadInput) {
  const testing::TemporaryDirectory dir("capture_import_bad");
  const auto folder = dir / "studio";
  make_studio_folder(folder);
  io::CaptureImportOptions options;
  options.folder = folder;
  expect_bad_input([&] { io::import_capture(options); }, "camera images but no calibration");
  options.calibration = folder / "calibration" / "rig.json";
  std::filesystem::create_directories(folder / "walk" / "images" / "cam07");
  expect_bad_input([&] { io::import_capture(options); }, "cam07': images of a camera the calibration does not have");
  std::filesystem::remove(folder / "walk" / "images" / "cam07");
  std::filesystem::remove(folder / "walk" / "images" / "cam01" / "img2.png");
  expect_bad_input([&] { io::import_capture(options); }, "img2.png' (frame 2): missing image of camera 'cam01'");
  std::filesystem::remove_all(folder / "walk" / "images");
  std::filesystem::remove(folder / "run" / "run_9.obj");
  expect_bad_input([&] { io::import_capture(options); }, "frame 9 is missing between 8 and 11");
  std::filesystem::copy_file(folder / "run" / "run_8.obj", folder / "run" / "run_9.obj");
  core::write_mesh(folder / "run" / "run_8.ply", testing::make_sphere(6, 8));
  expect_bad_input([&] { io::import_capture(options); }, "several numbered mesh series");
  options.mesh_format = "obj";
  EXPECT_EQ(io::import_capture(options).sequences[0].count, 4);
  std::filesystem::remove_all(folder / "walk");
  std::filesystem::remove_all(folder / "run");
  expect_bad_input([&] { io::import_capture(options); }, "no sequence");
}

}  // namespace
}  // namespace surfcap
