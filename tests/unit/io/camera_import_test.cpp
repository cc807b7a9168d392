#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <string>
#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/io/camera_import.hpp"
#include "surfcap/render/camera.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using testing::expect_bad_input;

using testing::write_text;

std::string numbers(std::initializer_list<double> values, const char* separator = " ") {
  std::string text;
  char buffer[40];
  for (const double value : values) {
    std::snprintf(buffer, sizeof buffer, "%.17g", value);
    text += (text.empty() ? "" : separator) + std::string(buffer);
  }
  return text;
}

/// Points spread through the volume the ring of cameras looks at.
std::vector<Eigen::Vector3d> known_points() {
  std::vector<Eigen::Vector3d> points;
  for (double x = -0.6; x <= 0.6; x += 0.3)
    for (double y = 0.1; y <= 1.9; y += 0.45)
      for (double z = -0.5; z <= 0.5; z += 0.25) points.emplace_back(x, y, z);
  return points;
}

std::vector<core::CaptureCamera> ring(int count) {
  std::vector<core::CaptureCamera> cameras;
  for (const auto& camera : render::ring_cameras(count, 3.0, 1.4, Eigen::Vector3d(0, 1, 0), 55, 800, 600))
    cameras.push_back(render::to_capture_camera(camera));
  return cameras;
}

/// A COLMAP model's pixel (COLMAP's convention: the top-left pixel's centre at (0.5, 0.5)),
/// written out independently of the importer: params as in cameras.txt.
Eigen::Vector2d colmap_pixel(const std::string& model, const std::vector<double>& p, const core::CaptureCamera& pose,
                             const Eigen::Vector3d& world) {
  const Eigen::Vector3d x = pose.R * world + pose.t;
  const double u = x.x() / x.z(), v = x.y() / x.z();
  double du = 0, dv = 0, fx = p[0], fy = p[0], cx = p[1], cy = p[2];
  const double r2 = u * u + v * v;
  if (model == "SIMPLE_RADIAL") du = u * p[3] * r2, dv = v * p[3] * r2;
  if (model == "RADIAL") du = u * (p[3] * r2 + p[4] * r2 * r2), dv = v * (p[3] * r2 + p[4] * r2 * r2);
  if (model == "PINHOLE" || model == "OPENCV" || model == "FULL_OPENCV") fy = p[1], cx = p[2], cy = p[3];
  if (model == "OPENCV" || model == "FULL_OPENCV") {
    const double k1 = p[4], k2 = p[5], p1 = p[6], p2 = p[7], k3 = model == "FULL_OPENCV" ? p[8] : 0.0;
    const double radial = k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
    du = u * radial + 2 * p1 * u * v + p2 * (r2 + 2 * u * u);
    dv = v * radial + 2 * p2 * u * v + p1 * (r2 + 2 * v * v);
  }
  return {fx * (u + du) + cx, fy * (v + dv) + cy};
}

TEST(CameraImport, ColmapModelsReproduceTheirProjections) {
  const testing::TemporaryDirectory dir("colmap_import");
  const auto poses = ring(6);
  struct Model {
    std::string name;
    std::vector<double> params;
  };
  const std::vector<Model> models = {
      {"SIMPLE_PINHOLE", {610.5, 400.25, 300.75}},
      {"PINHOLE", {612.0, 608.5, 398.0, 301.5}},
      {"SIMPLE_RADIAL", {605.0, 401.0, 299.0, -0.08}},
      {"RADIAL", {600.0, 400.5, 300.5, -0.12, 0.03}},
      {"OPENCV", {615.0, 611.0, 402.0, 298.0, -0.1, 0.02, 0.001, -0.0015}},
      {"FULL_OPENCV", {615.0, 611.0, 402.0, 298.0, -0.1, 0.02, 0.001, -0.0015, 0.004, 0, 0, 0}}};
  std::string cameras_txt = "# Camera list with one line of data per camera:\n", images_txt = "# Image list\n";
  for (std::size_t c = 0; c < models.size(); ++c) {
    cameras_txt += std::to_string(c + 1) + " " + models[c].name + " 800 600";
    for (const double value : models[c].params) cameras_txt += " " + numbers({value});
    cameras_txt += "\n";
    const Eigen::Quaterniond q(poses[c].R);
    images_txt += std::to_string(c + 1) + " " + numbers({q.w(), q.x(), q.y(), q.z(), poses[c].t.x(), poses[c].t.y(), poses[c].t.z()}) +
                  " " + std::to_string(c + 1) + " " + poses[c].name + "/000000.png\n";
    images_txt += c % 2 ? "\n" : "12.5 40.25 -1 300.0 20.0 17\n";  // POINTS2D, empty or not
  }
  write_text(dir / "cameras.txt", cameras_txt);
  write_text(dir / "images.txt", images_txt);

  const auto imported = io::read_colmap_cameras(dir.path());
  ASSERT_EQ(imported.size(), models.size());
  core::write_cameras(dir / "cameras.json", imported);
  const auto reread = core::read_cameras(dir / "cameras.json");
  double worst = 0;
  for (std::size_t c = 0; c < models.size(); ++c) {
    EXPECT_EQ(imported[c].name, poses[c].name);
    EXPECT_EQ(imported[c].width, 800);
    for (const auto& point : known_points()) {
      // OpenCV's convention puts the top-left pixel's centre at (0, 0).
      const Eigen::Vector2d expected = colmap_pixel(models[c].name, models[c].params, poses[c], point) - Eigen::Vector2d(0.5, 0.5);
      worst = std::max(worst, (io::project(imported[c], point) - expected).norm());
      worst = std::max(worst, (io::project(reread[c], point) - expected).norm());
    }
  }
  EXPECT_LT(worst, 1e-6);
}

std::string yaml_matrix(const char* key, int rows, int cols, const double* data) {
  std::string text = std::string("   ") + key + ": !!opencv-matrix\n      rows: " + std::to_string(rows) +
                     "\n      cols: " + std::to_string(cols) + "\n      dt: d\n      data: [ ";
  char buffer[40];
  for (int i = 0; i < rows * cols; ++i) {
    std::snprintf(buffer, sizeof buffer, "%.17g", data[i]);
    text += (i ? ", " : "") + std::string(buffer);
  }
  return text + " ]\n";
}

std::string xml_matrix(const char* key, int rows, int cols, const double* data) {
  std::string text = std::string("    <") + key + " type_id=\"opencv-matrix\"><rows>" + std::to_string(rows) +
                     "</rows><cols>" + std::to_string(cols) + "</cols><dt>d</dt><data>";
  char buffer[40];
  for (int i = 0; i < rows * cols; ++i) {
    std::snprintf(buffer, sizeof buffer, " %.17g", data[i]);
    text += buffer;
  }
  return text + "</data></" + key + ">\n";
}

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

TEST(CameraImport, OpenCvFileStorageYamlAndXmlReproduceTheCameras) {
  const testing::TemporaryDirectory dir("opencv_import");
  auto cameras = ring(4);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    cameras[c].K(0, 0) += 3.0 * static_cast<double>(c);
    cameras[c].distortion << -0.1 + 0.01 * static_cast<double>(c), 0.02, 0.001, -0.002, 0.003;
  }
  // YAML: cameras as top-level maps, R as a matrix or as a Rodrigues vector; millimetres.
  std::string yaml = "%YAML:1.0\n---\n";
  for (std::size_t c = 0; c < 2; ++c) {
    const RowMajor3 K = cameras[c].K, R = cameras[c].R;
    const Eigen::Vector3d t = cameras[c].t * 1000.0;
    yaml += cameras[c].name + ":\n" + yaml_matrix("camera_matrix", 3, 3, K.data()) +
            yaml_matrix("distortion_coefficients", 1, 5, cameras[c].distortion.data());
    if (c == 0) {
      yaml += yaml_matrix("R", 3, 3, R.data());
    } else {
      const Eigen::AngleAxisd axis(cameras[c].R);
      const Eigen::Vector3d rvec = axis.axis() * axis.angle();
      yaml += yaml_matrix("rvec", 3, 1, rvec.data());
    }
    yaml += yaml_matrix("T", 3, 1, t.data()) + "   image_width: 800\n   image_height: 600\n";
  }
  write_text(dir / "rig.yml", yaml);
  // XML: a "cameras" sequence with names, 8 distortion values (k4..k6 zero) and image_size.
  std::string xml = "<?xml version=\"1.0\"?>\n<opencv_storage>\n<cameras>\n";
  for (std::size_t c = 2; c < 4; ++c) {
    const RowMajor3 K = cameras[c].K, R = cameras[c].R;
    const Eigen::Vector3d t = cameras[c].t * 1000.0;
    double dist[8] = {};
    for (int k = 0; k < 5; ++k) dist[k] = cameras[c].distortion(k);
    xml += "  <_>\n    <name>" + cameras[c].name + "</name>\n" + xml_matrix("K", 3, 3, K.data()) +
           xml_matrix("dist", 1, 8, dist) + xml_matrix("R", 3, 3, R.data()) + xml_matrix("t", 3, 1, t.data()) +
           "    <image_size>800 600</image_size>\n  </_>\n";
  }
  write_text(dir / "rig.xml", xml + "</cameras>\n</opencv_storage>\n");

  auto imported = io::read_opencv_cameras(dir / "rig.yml");
  for (const auto& camera : io::read_opencv_cameras(dir / "rig.xml")) imported.push_back(camera);
  io::scale_translations(imported, 0.001);
  ASSERT_EQ(imported.size(), cameras.size());
  core::write_cameras(dir / "cameras.json", imported);
  const auto reread = core::read_cameras(dir / "cameras.json");
  double worst = 0;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    EXPECT_EQ(imported[c].name, cameras[c].name);
    EXPECT_EQ(imported[c].height, 600);
    for (const auto& point : known_points()) {
      const Eigen::Vector2d expected = io::project(cameras[c], point);
      worst = std::max(worst, (io::project(imported[c], point) - expected).norm());
      worst = std::max(worst, (io::project(reread[c], point) - expected).norm());
    }
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(CameraImport, DistortedProjectionFollowsOpenCv) {
  core::CaptureCamera camera;
  camera.K << 500, 0, 320, 0, 400, 240, 0, 0, 1;
  camera.distortion << 0.1, 0, 0, 0, 0;
  // x/z = 0.5, y/z = 0: r² = 0.25, the radial factor 1.025 moves the pixel to 320 + 500·0.5125.
  const Eigen::Vector2d pixel = io::project(camera, Eigen::Vector3d(1, 0, 2));
  EXPECT_NEAR(pixel.x(), 320 + 500 * 0.5125, 1e-12);
  EXPECT_NEAR(pixel.y(), 240, 1e-12);
  camera.distortion << 0, 0, 0.01, 0.02, 0;  // tangential: x += p2(r² + 2x²), y += p1(r² + 2y²)
  const Eigen::Vector2d tangential = io::project(camera, Eigen::Vector3d(1, 0, 2));
  EXPECT_NEAR(tangential.x(), 320 + 500 * (0.5 + 0.02 * 0.75), 1e-12);
  EXPECT_NEAR(tangential.y(), 240 + 400 * 0.01 * 0.25, 1e-12);
}

TEST(CameraImport, BadCalibrationsNameFileAndLine) {
  const testing::TemporaryDirectory dir("bad_calibrations");
  write_text(dir / "cameras.txt", "1 OPENCV_FISHEYE 800 600 600 600 400 300 0 0 0 0\n");
  write_text(dir / "images.txt", "1 1 0 0 0 0 0 3 1 cam00.png\n\n");
  expect_bad_input([&] { io::read_colmap_cameras(dir.path()); }, "cameras.txt': line 1: camera model OPENCV_FISHEYE");
  write_text(dir / "cameras.txt", "1 FULL_OPENCV 800 600 600 600 400 300 0 0 0 0 0 0.1 0 0\n");
  expect_bad_input([&] { io::read_colmap_cameras(dir.path()); }, "rational coefficients");
  write_text(dir / "cameras.txt", "1 PINHOLE 800 600 600 nan 400 300\n");
  expect_bad_input([&] { io::read_colmap_cameras(dir.path()); }, "line 1: 'nan' is not a finite number");
  write_text(dir / "cameras.txt", "1 PINHOLE 800 600 600 600 400 300\n");
  write_text(dir / "images.txt", "1 1 0 0 0 0 0 3 2 cam00.png\n\n");
  expect_bad_input([&] { io::read_colmap_cameras(dir.path()); }, "images.txt': line 1: camera 2 is not in cameras.txt");
  write_text(dir / "images.txt", "1 1 0 0 0 0 0 3 1 a/cam00.png\n\n2 1 0 0 0 0 0 3 1 a/cam01.png\n\n");
  expect_bad_input([&] { io::read_colmap_cameras(dir.path()); }, "a second image of camera 'a'");
  std::filesystem::remove(dir / "images.txt");
  expect_bad_input([&] { io::read_colmap_cameras(dir.path()); }, "images.txt': missing");

  write_text(dir / "bad.yml", "%YAML:1.0\n---\ncam0:\n   K: [ 1, 0, 0, 0, 1, 0, 0, 0, 1 ]\n");
  expect_bad_input([&] { io::read_opencv_cameras(dir / "bad.yml"); }, "camera 'cam0': no R");
  write_text(dir / "bad.yml", "this is: [not, : yaml");
  expect_bad_input([&] { io::read_opencv_cameras(dir / "bad.yml"); }, "bad.yml'");
  write_text(dir / "bad.yml",
             "%YAML:1.0\n---\ncam0:\n   K: [ 1, 0, 0, 0, 1, 0, 0, 0, 1 ]\n   R: [ 2, 0, 0, 0, 1, 0, 0, 0, 1 ]\n"
             "   t: [ 0, 0, 0 ]\n   width: 10\n   height: 10\n");
  expect_bad_input([&] { io::read_opencv_cameras(dir / "bad.yml"); }, "R is not a rotation");
}

}  // namespace
}  // namespace surfcap
