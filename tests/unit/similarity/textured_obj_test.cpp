#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/similarity/shape_histogram.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

/// A coloured, person-proportioned ellipsoid as a studio PLY frame would hold it (8-bit colours).
core::Mesh coloured_frame() {
  core::Mesh mesh = testing::make_sphere(24, 36, 1.0);
  mesh.V = mesh.V * Eigen::Vector3d(0.25, 0.9, 0.18).asDiagonal();
  mesh.V.col(1).array() += 0.9;
  mesh.colors.resize(mesh.vertex_count(), 3);
  for (long v = 0; v < mesh.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k)
      mesh.colors(v, k) = std::round(255 * (0.5 + 0.45 * std::sin(7 * mesh.V(v, k) + 2 * k))) / 255.0;
  return mesh;
}

/// `mesh` as OBJ + MTL + PNG atlas the way texturing tools write it: two charts (faces left and
/// right of x = 0), one texel per chart vertex holding its colour, per-corner UVs at texel centres,
/// and the positions of the seam vertices written again for the second chart.
void write_textured_obj(const core::Mesh& mesh, const std::filesystem::path& obj) {
  const long n = mesh.vertex_count();
  std::vector<int> chart(static_cast<std::size_t>(mesh.face_count()));
  std::vector<std::array<long, 2>> slot(static_cast<std::size_t>(n), {-1, -1});
  long slots = 0;
  for (long f = 0; f < mesh.face_count(); ++f) {
    const double x = mesh.V(mesh.F(f, 0), 0) + mesh.V(mesh.F(f, 1), 0) + mesh.V(mesh.F(f, 2), 0);
    chart[static_cast<std::size_t>(f)] = x < 0 ? 0 : 1;
    for (int k = 0; k < 3; ++k) {
      long& s = slot[static_cast<std::size_t>(mesh.F(f, k))][static_cast<std::size_t>(chart[static_cast<std::size_t>(f)])];
      if (s < 0) s = slots++;
    }
  }
  const int width = 64, height = static_cast<int>((slots + width - 1) / width);
  render::Image atlas(width, height, Eigen::Vector3d(1, 0, 1));
  std::vector<long> duplicate(static_cast<std::size_t>(n), -1);  // OBJ index of a seam vertex's second copy
  long next = n;
  for (long v = 0; v < n; ++v) {
    for (int c = 0; c < 2; ++c) {
      const long s = slot[static_cast<std::size_t>(v)][static_cast<std::size_t>(c)];
      if (s >= 0) atlas.set(static_cast<int>(s % width), static_cast<int>(s / width), mesh.colors.row(v).transpose());
    }
    if (slot[static_cast<std::size_t>(v)][0] >= 0 && slot[static_cast<std::size_t>(v)][1] >= 0)
      duplicate[static_cast<std::size_t>(v)] = next++;
  }
  std::filesystem::create_directories(obj.parent_path() / "textures");
  render::write_png(obj.parent_path() / "textures" / "atlas.png", atlas);
  testing::write_text(obj.parent_path() / "frame.mtl", "newmtl skin\nKd 1 1 1\nmap_Kd textures/atlas.png\n");
  std::ofstream out(obj);
  out << "mtllib frame.mtl\n";
  char line[160];
  for (long v = 0; v < n; ++v) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
    out << line;
  }
  for (long v = 0; v < n; ++v)
    if (duplicate[static_cast<std::size_t>(v)] >= 0) {
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
      out << line;
    }
  for (long s = 0; s < slots; ++s) {
    std::snprintf(line, sizeof line, "vt %.17g %.17g\n", (static_cast<double>(s % width) + 0.5) / width,
                  1.0 - (static_cast<double>(s / width) + 0.5) / height);
    out << line;
  }
  out << "usemtl skin\n";
  for (long f = 0; f < mesh.face_count(); ++f) {
    const int c = chart[static_cast<std::size_t>(f)];
    out << "f";
    for (int k = 0; k < 3; ++k) {
      const long v = mesh.F(f, k);
      const long position = c == 1 && duplicate[static_cast<std::size_t>(v)] >= 0 ? duplicate[static_cast<std::size_t>(v)] : v;
      out << " " << position + 1 << "/" << slot[static_cast<std::size_t>(v)][static_cast<std::size_t>(c)] + 1;
    }
    out << "\n";
  }
}

TEST(TexturedObj, GivesThePlyFormsHistogramAndColours) {
  const testing::TemporaryDirectory dir("textured_obj_form");
  core::write_mesh(dir / "000000.ply", coloured_frame());
  const core::Mesh from_ply = core::read_reconstruction(dir / "000000.ply", 0);
  write_textured_obj(from_ply, dir / "obj" / "000000.obj");
  const core::Mesh from_obj = core::read_reconstruction(dir / "obj" / "000000.obj", 0);

  ASSERT_EQ(from_obj.vertex_count(), from_ply.vertex_count());  // the seams are welded
  EXPECT_EQ(from_obj.V, from_ply.V);
  EXPECT_EQ(from_obj.F, from_ply.F);
  ASSERT_TRUE(from_obj.has_colors());
  EXPECT_LE((from_obj.colors - from_ply.colors).cwiseAbs().maxCoeff(), 2.0 / 255);
  const similarity::ShapeHistogramOptions options;
  const Eigen::VectorXd a = similarity::shape_histogram(from_ply, options);
  const Eigen::VectorXd b = similarity::shape_histogram(from_obj, options);
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace surfcap
