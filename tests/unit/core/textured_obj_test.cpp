#include <gtest/gtest.h>

#include <string>

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/render/png.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using testing::expect_bad_input;

using testing::write_text;

const char* kQuad =
    "mtllib quad.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0.25 0.5\nvt 0.75 0.5\nvt 0.5 0.5\nvt 0 0.5\n"
    "usemtl paint\n"
    "f 1/1 2/2 3/3 4/4\n";

/// A 2×1 texture: red on the left texel, blue on the right.
void write_two_texels(const std::filesystem::path& path) {
  render::Image image(2, 1);
  image.set(0, 0, Eigen::Vector3d(1, 0, 0));
  image.set(1, 0, Eigen::Vector3d(0, 0, 1));
  render::write_png(path, image);
}

TEST(TexturedObj, CornersSampleTheTextureBilinearly) {
  const testing::TemporaryDirectory dir("textured_obj_bilinear");
  write_two_texels(dir / "two.png");
  write_text(dir / "quad.mtl", "newmtl paint\nKd 0 1 0\nmap_Kd two.png\n");
  write_text(dir / "quad.obj", kQuad);
  const core::Mesh mesh = core::read_mesh(dir / "quad.obj");
  ASSERT_EQ(mesh.face_count(), 2);  // the quad as a fan
  ASSERT_TRUE(mesh.has_colors());
  EXPECT_FALSE(mesh.has_uvs());
  // u = 0.25 and 0.75 are the texel centres; 0.5 is half-way; 0 wraps (repeat) to half-way too.
  EXPECT_TRUE(mesh.colors.row(0).isApprox(Eigen::RowVector3d(1, 0, 0)));
  EXPECT_TRUE(mesh.colors.row(1).isApprox(Eigen::RowVector3d(0, 0, 1)));
  EXPECT_TRUE(mesh.colors.row(2).isApprox(Eigen::RowVector3d(0.5, 0, 0.5)));
  EXPECT_TRUE(mesh.colors.row(3).isApprox(Eigen::RowVector3d(0.5, 0, 0.5)));
  // With "-clamp on", u = 0 is the left texel.
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd -clamp on two.png\n");
  EXPECT_TRUE(core::read_mesh(dir / "quad.obj").colors.row(3).isApprox(Eigen::RowVector3d(1, 0, 0)));
  // Without a texture the diffuse colour is used.
  write_text(dir / "quad.mtl", "newmtl paint\nKd 0 1 0\n");
  EXPECT_TRUE(core::read_mesh(dir / "quad.obj").colors.row(2).isApprox(Eigen::RowVector3d(0, 1, 0)));
}

TEST(TexturedObj, SeamCopiesAreWeldedAndCornerColoursAveraged) {
  const testing::TemporaryDirectory dir("textured_obj_seam");
  write_two_texels(dir / "two.png");
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd two.png\n");
  // Two triangles sharing the edge 2-3, whose positions the second triangle repeats (5, 6).
  write_text(dir / "seam.obj",
             "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 1 0 0\nv 1 1 0\nv 2 1 0\n"
             "vt 0.25 0.5\nvt 0.75 0.5\nusemtl paint\nf 1/1 2/1 3/1\nf 4/2 6/2 5/2\n");
  const core::Mesh mesh = core::read_mesh(dir / "seam.obj");
  ASSERT_EQ(mesh.vertex_count(), 4);
  EXPECT_EQ(mesh.F(1, 0), 1);
  EXPECT_EQ(mesh.F(1, 2), 2);
  EXPECT_EQ(core::check_mesh(mesh).boundary_edges, 4);  // one surface, not two triangles
  EXPECT_TRUE(mesh.colors.row(0).isApprox(Eigen::RowVector3d(1, 0, 0)));
  EXPECT_TRUE(mesh.colors.row(1).isApprox(Eigen::RowVector3d(0.5, 0, 0.5)));  // one red, one blue corner
  EXPECT_TRUE(mesh.colors.row(3).isApprox(Eigen::RowVector3d(0, 0, 1)));
}

TEST(TexturedObj, BadReferencesNameTheFile) {
  const testing::TemporaryDirectory dir("textured_obj_bad");
  write_two_texels(dir / "two.png");
  write_text(dir / "quad.obj", kQuad);
  expect_bad_input([&] { core::read_mesh(dir / "quad.obj", {}, 7); }, "quad.mtl' (frame 7): missing material library");
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd ../two.png\n");
  expect_bad_input([&] { core::read_mesh(dir / "quad.obj"); }, "must be a relative path inside the file's folder");
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd /etc/passwd\n");
  expect_bad_input([&] { core::read_mesh(dir / "quad.obj"); }, "must be a relative path inside");
  write_text(dir / "quad.mtl", "newmtl other\nmap_Kd two.png\n");
  expect_bad_input([&] { core::read_mesh(dir / "quad.obj"); }, "material 'paint' is not defined");
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd missing.png\n");
  expect_bad_input([&] { core::read_mesh(dir / "quad.obj"); }, "missing.png");
  write_text(dir / "broken.png", "not a png");
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd broken.png\n");
  expect_bad_input([&] { core::read_mesh(dir / "quad.obj"); }, "broken.png'");
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd -s 2 2 two.png\n");
  expect_bad_input([&] { core::read_mesh(dir / "quad.obj"); }, "option '-s' is not supported");
  // Corrupt geometry stays corrupt geometry.
  write_text(dir / "quad.mtl", "newmtl paint\nmap_Kd two.png\n");
  write_text(dir / "nan.obj", "mtllib quad.mtl\nv 0 0 nan\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl paint\nf 1/1 2/1 3/1\n");
  expect_bad_input([&] { core::read_mesh(dir / "nan.obj"); }, "NaN");
  write_text(dir / "index.obj", "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl paint\nf 1/1 2/2 3/1\n");
  expect_bad_input([&] { core::read_mesh(dir / "index.obj"); }, "refers to a missing element");
}

}  // namespace
}  // namespace surfcap
