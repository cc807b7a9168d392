#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/render/colormap.hpp"
#include "surfcap/render/contact_sheet.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/render/rasterizer.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

render::Camera front_camera(int width = 160, int height = 120) {
  return render::look_at("front", Eigen::Vector3d(0, 0, 3), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 40,
                         width, height);
}

TEST(Camera, LookAtFollowsOpenCvConvention) {
  const auto camera = front_camera();
  const Eigen::Vector2d centre = camera.project(Eigen::Vector3d::Zero());
  EXPECT_NEAR(centre.x(), 79.5, 1e-9);
  EXPECT_NEAR(centre.y(), 59.5, 1e-9);
  EXPECT_NEAR(camera.to_camera(Eigen::Vector3d::Zero()).z(), 3.0, 1e-12);  // z forward
  EXPECT_LT(camera.project(Eigen::Vector3d(0, 1, 0)).y(), centre.y());  // world up is image up (smaller y)
  EXPECT_GT(camera.project(Eigen::Vector3d(1, 0, 0)).x(), centre.x());  // seen from +z looking at -z, +x is on the right
  EXPECT_TRUE((camera.centre() - Eigen::Vector3d(0, 0, 3)).norm() < 1e-12);
  EXPECT_NEAR(camera.R.determinant(), 1.0, 1e-12);
}

TEST(Camera, RingCamerasSurroundTheTarget) {
  const Eigen::Vector3d target(0, 1, 0);
  const auto cameras = render::ring_cameras(8, 4.0, 1.5, target, 40, 64, 48);
  ASSERT_EQ(cameras.size(), 8u);
  for (const auto& camera : cameras) {
    EXPECT_NEAR(std::hypot(camera.centre().x(), camera.centre().z()), 4.0, 1e-9);
    EXPECT_NEAR(camera.centre().y(), 1.5, 1e-9);
    const Eigen::Vector2d p = camera.project(target);
    EXPECT_NEAR(p.x(), 31.5, 1e-9);
    EXPECT_NEAR(p.y(), 23.5, 1e-9);
  }
  EXPECT_EQ(cameras[3].name, "cam03");
}

TEST(Camera, JsonRoundTripAndValidation) {
  testing::TemporaryDirectory dir("render-cameras");
  const auto cameras = render::ring_cameras(3, 2.0, 1.0, Eigen::Vector3d(0, 1, 0), 50, 64, 48);
  render::write_cameras(dir / "cameras.json", cameras);
  const auto read = render::read_cameras(dir / "cameras.json");
  ASSERT_EQ(read.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(read[i].name, cameras[i].name);
    EXPECT_TRUE(read[i].K.isApprox(cameras[i].K));
    EXPECT_TRUE(read[i].R.isApprox(cameras[i].R));
    EXPECT_LT((read[i].t - cameras[i].t).norm(), 1e-12);
  }
  auto document = core::read_json_file(dir / "cameras.json");
  document["cameras"][1]["R"] = std::vector<double>{2, 0, 0, 0, 1, 0, 0, 0, 1};
  core::write_json_file(dir / "bad.json", document);
  try {
    render::read_cameras(dir / "bad.json");
    FAIL() << "a non-rotation R was accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::bad_input);
  }
}

TEST(Rasterizer, SphereSilhouetteDepthAndColour) {
  core::Mesh sphere = testing::make_sphere(32, 64, 0.5);
  sphere.colors = Eigen::MatrixXd::Constant(sphere.vertex_count(), 3, 0.0);
  sphere.colors.col(1).setConstant(1.0);  // green
  const auto camera = front_camera(200, 200);
  render::RenderOptions options;
  options.background = Eigen::Vector3d(0, 0, 1);
  options.ambient = 1.0;
  options.diffuse = 0.0;
  const auto rendering = render::render_mesh(sphere, camera, options);
  const std::size_t centre = 100 * 200 + 100;
  EXPECT_NEAR(rendering.depth[centre], 2.5, 0.005);  // 3 m away, radius 0.5
  EXPECT_GE(rendering.face[centre], 0);
  EXPECT_TRUE(rendering.image.get(100, 100).isApprox(Eigen::Vector3d(0, 1, 0), 1e-6));
  EXPECT_TRUE(rendering.image.get(0, 0).isApprox(Eigen::Vector3d(0, 0, 1), 1e-6));
  // Silhouette radius: the sphere subtends asin(r/d) from the centre.
  const double focal = camera.K(0, 0);
  const double expected = focal * std::tan(std::asin(0.5 / 3.0));
  long covered = 0;
  for (int f : rendering.face) covered += f >= 0;
  const double radius = std::sqrt(covered / M_PI);
  EXPECT_NEAR(radius, expected, 0.02 * expected);
}

TEST(Rasterizer, NearerSurfaceWinsAndLambertDarkensGrazingLight) {
  core::Mesh near = testing::make_sphere(16, 32, 0.3);
  core::Mesh far = near;
  far.V.col(2).array() -= 1.0;  // behind
  core::Mesh both;
  both.V.resize(near.vertex_count() * 2, 3);
  both.V << near.V, far.V;
  both.F.resize(near.face_count() * 2, 3);
  both.F << near.F, (far.F.array() + static_cast<int>(near.vertex_count())).matrix();
  render::RenderOptions options;
  options.ambient = 0.2;
  options.diffuse = 0.8;
  const auto rendering = render::render_mesh(both, front_camera(120, 120), options);
  const int centre_face = rendering.face[60 * 120 + 60];
  EXPECT_LT(centre_face, near.face_count());
  EXPECT_NEAR(rendering.depth[60 * 120 + 60], 2.7, 0.01);
  // Headlight: the centre faces the light, the limb does not.
  const double centre = rendering.image.get(60, 60).x();
  int limb_x = 60;
  while (rendering.face[60 * 120 + limb_x + 1] >= 0) ++limb_x;
  EXPECT_GT(centre, 0.95 * 0.75);
  EXPECT_LT(rendering.image.get(limb_x, 60).x(), 0.6 * centre);
}

TEST(Rasterizer, VisibilityIsTheRenderingsDepthAndFaceBuffers) {
  core::Mesh near = testing::make_sphere(16, 32, 0.3);
  near.V.col(2).array() += 0.5;
  const core::Mesh far = testing::make_sphere(16, 32, 0.6);
  core::Mesh both = far;
  both.V.conservativeResize(far.V.rows() + near.V.rows(), 3);
  both.V.bottomRows(near.V.rows()) = near.V;
  both.F.conservativeResize(far.F.rows() + near.F.rows(), 3);
  both.F.bottomRows(near.F.rows()) = near.F.array() + static_cast<int>(far.V.rows());
  const render::Camera camera = front_camera(120, 90);
  const render::Rendering rendering = render::render_mesh(both, camera);
  const render::Visibility visibility = render::render_visibility(both.V, both.F, camera);
  ASSERT_EQ(visibility.face.size(), rendering.face.size());
  EXPECT_EQ(visibility.face, rendering.face);
  EXPECT_EQ(visibility.depth, rendering.depth);
  long near_pixels = 0;
  for (const int f : visibility.face) near_pixels += f >= far.F.rows();
  EXPECT_GT(near_pixels, 500);  // the nearer sphere occludes the farther one in the middle
}

TEST(Png, RoundTripIsExactAndAtomic) {
  testing::TemporaryDirectory dir("render-png");
  render::Image image(7, 5, Eigen::Vector3d(0.2, 0.4, 0.6));
  image.set(3, 2, Eigen::Vector3d(1, 0, 0));
  render::write_png(dir / "a.png", image);
  const auto read = render::read_png(dir / "a.png");
  EXPECT_EQ(read.width, 7);
  EXPECT_EQ(read.height, 5);
  EXPECT_EQ(read.pixels, image.pixels);
  EXPECT_EQ(testing::count_hidden_files(dir.path()), 0);
  EXPECT_EQ(render::encode_png(image), render::encode_png(read));
  testing::write_text(dir / "bad.png", "not a png");
  EXPECT_THROW(render::read_png(dir / "bad.png"), core::Error);
}

TEST(Colormap, HeatRunsBlueToRed) {
  EXPECT_TRUE(render::heat_color(0).isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(render::heat_color(1).isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(render::heat_color(0.5).isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_TRUE(render::heat_color(7).isApprox(Eigen::Vector3d(1, 0, 0)));
  const Eigen::MatrixXd colors = render::heat_colors(Eigen::Vector3d(10, 15, 20), 10, 20);
  EXPECT_TRUE(colors.row(1).isApprox(Eigen::RowVector3d(0, 1, 0)));
  const auto image = render::matrix_image(Eigen::Matrix2d::Identity(), 0, 1, 3);
  EXPECT_EQ(image.width, 6);
  EXPECT_TRUE(image.get(0, 0).isApprox(Eigen::Vector3d(1, 0, 0), 1e-2));
  EXPECT_TRUE(image.get(5, 0).isApprox(Eigen::Vector3d(0, 0, 1), 1e-2));
}

TEST(ContactSheet, LaysOutCellsRowByRow) {
  std::vector<render::Image> images;
  for (int i = 0; i < 5; ++i) images.emplace_back(20, 10, Eigen::Vector3d(i / 5.0, 0, 0));
  render::ContactSheetOptions options;
  options.columns = 3;
  options.padding = 2;
  const auto sheet = render::contact_sheet(images, options);
  EXPECT_EQ(sheet.width, 3 * 20 + 4 * 2);
  EXPECT_EQ(sheet.height, 2 * 10 + 3 * 2);
  EXPECT_TRUE(sheet.get(2 + 22 + 5, 2 + 12 + 5).isApprox(images[4].get(0, 0), 1e-2));  // 5th: row 1, column 1
}

}  // namespace
}  // namespace surfcap
