#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using core::ExitCode;
using testing::TemporaryDirectory;
using testing::expect_bad_input;
using testing::signed_volume;

/// The sphere without the faces around `vertex` (a hole whose loop is the vertex's neighbours).
core::Mesh without_faces_around(const core::Mesh& mesh, std::vector<int> vertices) {
  std::vector<long> kept;
  for (long f = 0; f < mesh.F.rows(); ++f) {
    bool touches = false;
    for (int k = 0; k < 3; ++k) touches |= std::count(vertices.begin(), vertices.end(), mesh.F(f, k)) > 0;
    if (!touches) kept.push_back(f);
  }
  core::Mesh open = mesh;
  open.F.resize(static_cast<long>(kept.size()), 3);
  for (std::size_t k = 0; k < kept.size(); ++k) open.F.row(static_cast<long>(k)) = mesh.F.row(kept[k]);
  return open;
}

/// Every warning logged while the object lives.
class CapturedWarnings {
 public:
  CapturedWarnings() : sink_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64)) {
    previous_ = spdlog::default_logger();
    auto logger = std::make_shared<spdlog::logger>("capture", sink_);
    logger->set_level(spdlog::level::warn);
    spdlog::set_default_logger(logger);
  }
  ~CapturedWarnings() { spdlog::set_default_logger(previous_); }
  std::string text() const {
    std::string all;
    for (const auto& line : sink_->last_formatted()) all += line;
    return all;
  }

 private:
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> sink_;
  std::shared_ptr<spdlog::logger> previous_;
};

void expect_closed_manifold(const core::Mesh& mesh) {
  const core::MeshCheck check = core::check_mesh(mesh);
  EXPECT_TRUE(check.closed()) << check.summary();
  EXPECT_TRUE(check.manifold()) << check.summary();
  EXPECT_EQ(core::count_pinch_vertices(mesh), 0);
  EXPECT_EQ(check.unreferenced_vertices, 0);
}

TEST(MeshRepair, ClosedManifoldMeshIsUnchanged) {
  core::Mesh mesh = testing::make_sphere(8, 12);
  const core::Mesh original = mesh;
  const auto report = core::repair_mesh(mesh, {}, "sphere.ply", 3);
  EXPECT_FALSE(report.changed());
  EXPECT_EQ(mesh.V, original.V);
  EXPECT_EQ(mesh.F, original.F);
}

TEST(MeshRepair, SmallHolesAreFilledWithoutNewVertices) {
  const core::Mesh sphere = testing::make_sphere(40, 64);
  // Two holes: the 6 faces around a vertex of ring 9 and of ring 30 (hexagons ~0.5 m around,
  // under a quarter of the 3.5 m bounding-box diagonal).
  core::Mesh mesh = without_faces_around(sphere, {1 + 8 * 64 + 3, 1 + 29 * 64 + 9});
  core::Mesh colored = mesh;
  colored.colors = Eigen::MatrixXd::Zero(mesh.vertex_count(), 3);
  for (long v = 0; v < mesh.vertex_count(); ++v) colored.colors(v, v % 3) = 1.0;
  ASSERT_EQ(core::check_mesh(mesh).boundary_edges, 12);

  const auto report = core::repair_mesh(colored, {}, "open.ply", 5);
  expect_closed_manifold(colored);
  EXPECT_EQ(report.holes_filled, 2);
  EXPECT_EQ(report.largest_hole_edges, 6);
  EXPECT_LT(report.largest_hole_perimeter, 0.25 * core::bounding_box_diagonal(sphere.V));
  EXPECT_EQ(report.faces_added, 8);  // a hexagon takes 4 triangles
  EXPECT_EQ(report.vertices_dropped, 2);  // the two hole centres lost their faces
  EXPECT_EQ(colored.vertex_count(), sphere.vertex_count() - 2);
  EXPECT_EQ(colored.face_count(), sphere.face_count() - 12 + 8);
  // The patches are flat hexagons: the enclosed volume is the sphere's minus two thin caps.
  EXPECT_GT(signed_volume(colored), 0.999 * signed_volume(sphere));
  EXPECT_LT(signed_volume(colored), signed_volume(sphere));
  // Colours follow their vertices: every kept vertex keeps its position's colour.
  for (long v = 0; v < colored.vertex_count(); ++v) {
    long source = -1;
    for (long u = 0; u < mesh.vertex_count(); ++u)
      if (mesh.V.row(u) == colored.V.row(v)) source = u;
    ASSERT_GE(source, 0);
    EXPECT_EQ(colored.colors(v, source % 3), 1.0);
  }
}

TEST(MeshRepair, LargeHoleStaysAnErrorNamingFileAndFrame) {
  const core::Mesh sphere = testing::make_sphere(10, 64);
  std::vector<int> cap;  // the pole and rings 1..4 removed: ring 5 bounds a hole of 64 edges
  for (int v = 0; v <= 4 * 64; ++v) cap.push_back(v);
  core::Mesh mesh = without_faces_around(sphere, cap);
  expect_bad_input([&] { core::repair_mesh(mesh, {}, "walk/mesh/000012.ply", 12); },
                   "'walk/mesh/000012.ply' (frame 12)");
  expect_bad_input([&] { core::repair_mesh(mesh, {}, "walk/mesh/000012.ply", 12); }, "too large to fill");
  core::RepairLimits generous;
  generous.max_hole_edges = 80;
  expect_bad_input([&] { core::repair_mesh(mesh, generous, "walk/mesh/000012.ply", 12); },
                   "% of the bounding-box diagonal): too large to fill");  // 6.3 m around: still too wide
  generous.max_hole_perimeter = 2.0;
  core::repair_mesh(mesh, generous, "walk/mesh/000012.ply", 12);
  expect_closed_manifold(mesh);
}

TEST(MeshRepair, LargeHolesStayOpenWhereOpenSurfacesAreAccepted) {
  const core::Mesh sphere = testing::make_sphere(40, 64);
  std::vector<int> cut;  // the pole and rings 1..4 (a 64-edge hole) and the 6 faces around a vertex of ring 30
  for (int v = 0; v <= 4 * 64; ++v) cut.push_back(v);
  cut.push_back(1 + 29 * 64 + 9);
  core::Mesh mesh = without_faces_around(sphere, cut);
  core::Mesh strict = mesh;
  expect_bad_input([&] { core::repair_mesh(strict, {}, "walk/mesh/000012.ply", 12); },
                   "too large to fill");
  core::RepairLimits open;
  open.keep_large_holes_open = true;
  const auto report = core::repair_mesh(mesh, open, "walk/mesh/000012.ply", 12);
  EXPECT_EQ(report.holes_filled, 1);
  EXPECT_EQ(report.largest_hole_edges, 6);
  EXPECT_EQ(report.holes_open, 1);
  EXPECT_EQ(report.largest_open_hole_edges, 64);
  EXPECT_NE(report.summary().find("left 1 large hole open (largest 64 edges"), std::string::npos) << report.summary();
  const core::MeshCheck check = core::check_mesh(mesh);
  EXPECT_EQ(check.boundary_edges, 64);
  EXPECT_TRUE(check.manifold());
  EXPECT_EQ(core::count_pinch_vertices(mesh), 0);
}

TEST(MeshRepair, ManySmallHolesAreFilledWhereOpenSurfacesAreAccepted) {
  const core::Mesh sphere = testing::make_sphere(40, 48);
  std::vector<int> centres;
  for (int r = 4; r < 37; r += 7)
    for (int s = 0; s < 48; s += 16) centres.push_back(1 + (r - 1) * 48 + s);  // 15 separate hexagons
  core::Mesh mesh = without_faces_around(sphere, centres);
  core::RepairLimits open;
  open.keep_large_holes_open = true;
  const auto report = core::repair_mesh(mesh, open, "f.ply");
  EXPECT_EQ(report.holes_filled, 15);
  EXPECT_EQ(report.holes_open, 0);
  expect_closed_manifold(mesh);
}

TEST(MeshRepair, ManyHolesStayAnError) {
  const core::Mesh sphere = testing::make_sphere(40, 48);
  std::vector<int> centres;
  for (int r = 4; r < 37; r += 7)
    for (int s = 0; s < 48; s += 16) centres.push_back(1 + (r - 1) * 48 + s);  // 15 separate hexagons
  const core::Mesh mesh = without_faces_around(sphere, centres);
  core::Mesh copy = mesh;
  expect_bad_input([&] { core::repair_mesh(copy, {}, "f.ply"); }, "15 holes: too many");
}

TEST(MeshRepair, FinOnAnEdgeIsSplitOffAndDropped) {
  core::Mesh mesh = testing::make_sphere(8, 12);
  const core::Mesh sphere = mesh;
  const int a = mesh.F(20, 0), b = mesh.F(20, 1);
  // A third face on edge (a, b): a fin sticking out to a new vertex.
  mesh.V.conservativeResize(mesh.V.rows() + 1, 3);
  mesh.V.row(mesh.V.rows() - 1) = 1.5 * (mesh.V.row(a) + mesh.V.row(b)) / 2;
  mesh.F.conservativeResize(mesh.F.rows() + 1, 3);
  mesh.F.row(mesh.F.rows() - 1) << a, b, static_cast<int>(mesh.V.rows() - 1);
  ASSERT_EQ(core::check_mesh(mesh).non_manifold_edges, 1);

  const auto report = core::repair_mesh(mesh, {}, "fin.obj", 0);
  expect_closed_manifold(mesh);
  EXPECT_EQ(report.non_manifold_edges, 1);
  EXPECT_GT(report.vertices_duplicated, 0);
  EXPECT_EQ(report.debris_components, 1) << report.summary();  // the fin, cut off by the split
  EXPECT_EQ(mesh.vertex_count(), sphere.vertex_count());
  EXPECT_NEAR(signed_volume(mesh), signed_volume(sphere), 1e-9);  // the sphere itself is intact
}

TEST(MeshRepair, PinchVertexIsSplit) {
  // Two spheres touching at one vertex: sphere B's south pole is sphere A's north pole.
  const core::Mesh a = testing::make_sphere(6, 8);
  core::Mesh b = testing::make_sphere(6, 8);
  b.V.col(1).array() += 2.0;
  const long south_b = b.V.rows() - 1;
  core::Mesh mesh;
  mesh.V.resize(a.V.rows() + b.V.rows() - 1, 3);
  mesh.V << a.V, b.V.topRows(south_b);
  mesh.F.resize(a.F.rows() + b.F.rows(), 3);
  Eigen::MatrixXi fb = b.F.array() + static_cast<int>(a.V.rows());
  for (long f = 0; f < fb.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (b.F(f, k) == south_b) fb(f, k) = 0;  // a's north pole
  mesh.F << a.F, fb;
  long first = -1;
  ASSERT_EQ(core::count_pinch_vertices(mesh, &first), 1);
  ASSERT_EQ(first, 0);
  ASSERT_EQ(core::check_mesh(mesh).non_manifold_edges, 0);

  const auto report = core::repair_mesh(mesh, {}, "pinch.ply");
  expect_closed_manifold(mesh);
  EXPECT_EQ(report.non_manifold_vertices, 1);
  EXPECT_EQ(report.vertices_duplicated, 1);
  EXPECT_EQ(mesh.vertex_count(), a.vertex_count() + b.vertex_count());
  EXPECT_NEAR(signed_volume(mesh), signed_volume(a) + signed_volume(b), 1e-9);
}

TEST(MeshRepair, FlippedFacesAreReorientedOutward) {
  const core::Mesh sphere = testing::make_sphere(8, 12);
  for (const long flipped : {0L, 17L}) {  // face 0 flipped: the orientation follows it, then turns outward
    core::Mesh mesh = sphere;
    std::swap(mesh.F(flipped, 1), mesh.F(flipped, 2));
    const auto report = core::repair_mesh(mesh, {}, "flipped.ply");
    expect_closed_manifold(mesh);
    EXPECT_GT(report.faces_reoriented, 0);
    EXPECT_NEAR(signed_volume(mesh), signed_volume(sphere), 1e-12);
  }
}

TEST(MeshRepair, ManyNonManifoldEdgesStayAnError) {
  core::Mesh mesh = testing::make_sphere(8, 12);
  const long faces = mesh.F.rows();
  mesh.F.conservativeResize(faces + 30, 3);
  mesh.F.bottomRows(30) = mesh.F.topRows(30);  // 30 faces doubled: 90 edges with four faces
  expect_bad_input([&] { core::repair_mesh(mesh, {}, "doubled.ply", 7); }, "too many to repair");
}

TEST(MeshRepair, ReadReconstructionRepairsAndWarns) {
  TemporaryDirectory dir("mesh_repair");
  const core::Mesh open = without_faces_around(testing::make_sphere(40, 64), {1 + 19 * 64 + 5});
  core::write_mesh(dir / "frame.ply", open);
  CapturedWarnings warnings;
  core::RepairReport report;
  const core::Mesh mesh = core::read_reconstruction(dir / "frame.ply", 4, {}, &report);
  expect_closed_manifold(mesh);
  EXPECT_EQ(report.holes_filled, 1);
  const std::string logged = warnings.text();
  EXPECT_NE(logged.find("frame.ply' (frame 4): repaired: filled 1 hole (largest 6 edges, 4 faces added)"),
            std::string::npos)
      << logged;
}

}  // namespace
}  // namespace surfcap
