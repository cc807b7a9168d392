#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <limits>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using core::ExitCode;
using testing::TemporaryDirectory;
using testing::write_text;

core::Mesh colored_sphere() {
  core::Mesh mesh = testing::make_sphere(8, 12, 0.5);
  mesh.colors.resize(mesh.vertex_count(), 3);
  for (long v = 0; v < mesh.vertex_count(); ++v)
    mesh.colors.row(v) << (v % 7) / 6.0, (v % 5) / 4.0, (v % 3) / 2.0;  // exact in 8 bits? no: quantised
  return mesh;
}

/// Expects `action` to throw core::Error with `code` and a message containing `needle`.
template <class Action>
void expect_error(Action action, ExitCode code, const std::string& needle) {
  try {
    action();
    FAIL() << "expected an error containing '" << needle << "'";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(MeshIO, SphereIsClosedManifold) {
  const core::Mesh mesh = testing::make_sphere(8, 12);
  const core::MeshCheck check = core::check_mesh(mesh);
  EXPECT_TRUE(check.closed());
  EXPECT_TRUE(check.manifold());
  EXPECT_EQ(check.summary(), "ok");
  // Outward orientation: positive signed volume ≈ 4/3 π r³ (less for the polyhedron).
  double volume = 0;
  for (long f = 0; f < mesh.face_count(); ++f)
  {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  EXPECT_GT(volume, 0.8 * 4.0 / 3.0 * M_PI);
  EXPECT_LT(volume, 4.0 / 3.0 * M_PI);
}

class MeshRoundTrip : public ::testing::TestWithParam<std::pair<std::string, bool>> {};

TEST_P(MeshRoundTrip, KeepsGeometryConnectivityAndColours) {
  const auto [extension, binary] = GetParam();
  TemporaryDirectory dir("mesh_round_trip");
  const core::Mesh mesh = colored_sphere();
  const auto path = dir / ("sphere" + extension);
  core::write_mesh(path, mesh, {.binary = binary});
  const core::Mesh back = core::read_mesh(path);
  ASSERT_EQ(back.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(back.face_count(), mesh.face_count());
  EXPECT_LT((back.V - mesh.V).cwiseAbs().maxCoeff(), 1e-6);  // float32 in the file
  EXPECT_EQ(back.F, mesh.F);
  if (extension != ".obj") {  // OBJ has no standard per-vertex colour
    ASSERT_TRUE(back.has_colors());
    EXPECT_LT((back.colors - mesh.colors).cwiseAbs().maxCoeff(), 0.5 / 255.0 + 1e-9);
  }
  EXPECT_EQ(testing::count_hidden_files(dir.path()), 0);
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshRoundTrip,
                         ::testing::Values(std::make_pair(".ply", true), std::make_pair(".ply", false),
                                           std::make_pair(".obj", false), std::make_pair(".off", false)));

TEST(MeshIO, BinaryPlyWriteIsDeterministic) {
  TemporaryDirectory dir("mesh_deterministic");
  const core::Mesh mesh = colored_sphere();
  core::write_mesh(dir / "a.ply", mesh);
  core::write_mesh(dir / "b.ply", mesh);
  EXPECT_EQ(core::read_file(dir / "a.ply"), core::read_file(dir / "b.ply"));
}

TEST(MeshIO, ObjPolygonsAreTriangulated) {
  TemporaryDirectory dir("mesh_quad");
  write_text(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const core::Mesh mesh = core::read_mesh(dir / "quad.obj");
  EXPECT_EQ(mesh.face_count(), 2);
}

/// A PLY of one convex polygon of `corners` vertices on the unit circle, its list counted with
/// `count_type` (uchar, ushort or uint), ASCII or binary of either byte order.
std::string polygon_ply(int corners, const std::string& count_type, const std::string& format) {
  std::string text = "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(corners) +
                     "\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
                     "comment a comment between the face properties\nproperty list " + count_type +
                     " int vertex_indices\nend_header\n";
  if (format == "ascii") {
    for (int v = 0; v < corners; ++v)
      text += std::to_string(std::cos(2 * M_PI * v / corners)) + " " + std::to_string(std::sin(2 * M_PI * v / corners)) + " 0\n";
    text += std::to_string(corners);
    for (int v = 0; v < corners; ++v) text += " " + std::to_string(v);
    return text + "\n";
  }
  const bool big = format == "binary_big_endian";
  const auto append = [&](std::uint32_t bits, int size) {
    for (int k = 0; k < size; ++k) text.push_back(static_cast<char>(bits >> (8 * (big ? size - 1 - k : k)) & 0xff));
  };
  for (int v = 0; v < corners; ++v)
    for (const float c : {static_cast<float>(std::cos(2 * M_PI * v / corners)),
                          static_cast<float>(std::sin(2 * M_PI * v / corners)), 0.0f}) {
      std::uint32_t bits = 0;
      std::memcpy(&bits, &c, 4);
      append(bits, 4);
    }
  append(static_cast<std::uint32_t>(corners), count_type == "uchar" ? 1 : count_type == "ushort" ? 2 : 4);
  for (int v = 0; v < corners; ++v) append(static_cast<std::uint32_t>(v), 4);
  return text;
}

TEST(MeshIO, PlyListsCountedWithWiderIntegersAreRead) {
  TemporaryDirectory dir("mesh_wide_counts");
  // A polygon of n corners becomes n − 2 triangles, whatever the count type and encoding; one
  // of more than 255 corners too, though a uchar count cannot hold it.
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const std::string count_type : {"uchar", "ushort", "uint"})
      for (const int corners : {4, 300}) {
        if (count_type == "uchar" && corners > 255) continue;
        const auto path = dir / (format + "_" + count_type + "_" + std::to_string(corners) + ".ply");
        write_text(path, polygon_ply(corners, count_type, format));
        const core::Mesh mesh = core::read_mesh(path);
        EXPECT_EQ(mesh.vertex_count(), corners) << path;
        EXPECT_EQ(mesh.face_count(), corners - 2) << path;
        EXPECT_EQ(mesh.F.maxCoeff(), corners - 1) << path;
        EXPECT_NEAR(mesh.V(corners / 4, 1), std::sin(2 * M_PI * (corners / 4) / corners), 1e-5) << path;
      }
}

TEST(MeshIO, MissingFileIsIoError) {
  TemporaryDirectory dir("mesh_missing");
  expect_error([&] { core::read_mesh(dir / "nothing.ply", {}, 7); }, ExitCode::io, "nothing.ply");
}

TEST(MeshIO, UnknownExtensionIsBadArgument) {
  TemporaryDirectory dir("mesh_ext");
  write_text(dir / "mesh.stl", "solid x\nendsolid x\n");
  expect_error([&] { core::read_mesh(dir / "mesh.stl"); }, ExitCode::bad_arguments, "mesh.stl");
}

TEST(MeshIO, TruncatedBinaryPlyNamesFileAndFrame) {
  TemporaryDirectory dir("mesh_truncated");
  core::write_mesh(dir / "full.ply", colored_sphere());
  const std::string bytes = core::read_file(dir / "full.ply");
  write_text(dir / "cut.ply", bytes.substr(0, bytes.size() - 200));
  expect_error([&] { core::read_mesh(dir / "cut.ply", {}, 12); }, ExitCode::bad_input, "cut.ply' (frame 12)");
}

TEST(MeshIO, TruncatedAsciiPlyIsBadInput) {
  TemporaryDirectory dir("mesh_truncated_ascii");
  core::write_mesh(dir / "full.ply", colored_sphere(), {.binary = false});
  const std::string text = core::read_file(dir / "full.ply");
  write_text(dir / "cut.ply", text.substr(0, text.size() / 2));
  expect_error([&] { core::read_mesh(dir / "cut.ply"); }, ExitCode::bad_input, "cut.ply");
}

TEST(MeshIO, GarbageIsBadInput) {
  TemporaryDirectory dir("mesh_garbage");
  write_text(dir / "garbage.ply", "this is not a mesh at all\n\x01\x02\x03");
  expect_error([&] { core::read_mesh(dir / "garbage.ply"); }, ExitCode::bad_input, "garbage.ply");
}

TEST(MeshIO, EmptyMeshIsBadInput) {
  TemporaryDirectory dir("mesh_empty");
  write_text(dir / "empty.obj", "# nothing\n");
  expect_error([&] { core::read_mesh(dir / "empty.obj"); }, ExitCode::bad_input, "empty mesh");
}

TEST(MeshIO, NanCoordinatesAreBadInput) {
  TemporaryDirectory dir("mesh_nan");
  write_text(dir / "nan.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
  expect_error([&] { core::read_mesh(dir / "nan.ply", {}, 3); }, ExitCode::bad_input, "NaN/Inf");
}

TEST(MeshIO, InfCoordinatesInValidatedMesh) {
  core::Mesh mesh = testing::make_sphere(4, 6);
  mesh.V(5, 1) = std::numeric_limits<double>::infinity();
  expect_error([&] { core::validate_mesh(mesh, {}, "frame.ply", 9); }, ExitCode::bad_input, "(first: vertex 5)");
}

TEST(MeshIO, OutOfRangeFaceIsBadInput) {
  TemporaryDirectory dir("mesh_range");
  write_text(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
  expect_error([&] { core::read_mesh(dir / "range.obj"); }, ExitCode::bad_input, "range.obj");
}

TEST(MeshIO, DegenerateFacesAreBadInput) {
  core::Mesh mesh = testing::make_sphere(4, 6);
  mesh.F(3, 1) = mesh.F(3, 0);
  expect_error([&] { core::validate_mesh(mesh, {}, "x.ply"); }, ExitCode::bad_input, "face 3");
  core::Mesh flat = testing::make_sphere(4, 6);
  flat.V.row(flat.F(2, 2)) = flat.V.row(flat.F(2, 0));  // collapses faces around vertex F(2,2)
  expect_error([&] { core::validate_mesh(flat, {}, "flat.ply"); }, ExitCode::bad_input, "zero-area");
  core::MeshRequirements lenient;
  lenient.allow_zero_area_faces = true;
  EXPECT_GT(core::validate_mesh(flat, lenient, "flat.ply").zero_area_faces, 0);
}

TEST(MeshIO, NonManifoldEdgeIsReported) {
  TemporaryDirectory dir("mesh_nonmanifold");
  // Three triangles sharing the edge 1-2: a fin.
  write_text(dir / "fin.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\nv 1 0 1\nf 1 2 3\nf 2 4 3\nf 2 3 5\n");
  expect_error([&] { core::read_mesh(dir / "fin.obj", {}, 4); }, ExitCode::bad_input, "non-manifold");
  core::MeshRequirements lenient;
  lenient.allow_non_manifold = true;
  const core::Mesh mesh = core::read_mesh(dir / "fin.obj", lenient);
  EXPECT_EQ(mesh.vertex_count(), 5);  // as in the file: OpenMesh's vertex duplication is not seen
  EXPECT_EQ(mesh.face_count(), 3);
  EXPECT_EQ(core::check_mesh(mesh).non_manifold_edges, 1);
}

TEST(MeshIO, InconsistentOrientationIsNonManifold) {
  core::Mesh mesh = testing::make_sphere(4, 6);
  std::swap(mesh.F(0, 1), mesh.F(0, 2));
  EXPECT_GT(core::check_mesh(mesh).non_manifold_edges, 0);
}

TEST(MeshIO, OpenSurfaceAllowedUnlessRequired) {
  core::Mesh mesh = testing::make_sphere(4, 6);
  mesh.F.conservativeResize(mesh.face_count() - 1, 3);
  EXPECT_GT(core::validate_mesh(mesh, {}, "open.ply").boundary_edges, 0);
  core::MeshRequirements closed;
  closed.allow_open = false;
  expect_error([&] { core::validate_mesh(mesh, closed, "open.ply"); }, ExitCode::bad_input, "open");
}

TEST(MeshIO, UvsRoundTripThroughObj) {
  TemporaryDirectory dir("mesh_uv");
  core::Mesh mesh = testing::make_sphere(5, 8);
  mesh.uvs.resize(mesh.vertex_count(), 2);
  for (long v = 0; v < mesh.vertex_count(); ++v) mesh.uvs.row(v) << (v % 10) / 10.0, (v % 4) / 4.0;
  core::write_mesh(dir / "uv.obj", mesh);
  const core::Mesh back = core::read_mesh(dir / "uv.obj");
  ASSERT_TRUE(back.has_uvs());
  EXPECT_LT((back.uvs - mesh.uvs).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace surfcap

namespace surfcap {
namespace {

const char* kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(MeshPrecheck, MalformedAsciiNeverReachesOpenMesh) {
  // Each of these once made OpenMesh read uninitialised values (one allocated 21 GB).
  testing::TemporaryDirectory dir("mesh_precheck");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"nan.ply", std::string(kPlyHeader) + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"},
      {"word.ply", std::string(kPlyHeader) + "0 0 0\nabc 0 0\n0 1 0\n3 0 1 2\n"},
      {"inf.ply", std::string(kPlyHeader) + "0 0 0\n1 -inf 0\n0 1 0\n3 0 1 2\n"},
      {"short.ply", std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 1 0\n"},
      {"longlist.ply", std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 1 0\n200000 0 1 2\n"},
      {"nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"},
      {"short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"},
      {"noheader.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"},
  };
  for (const auto& [name, text] : cases) {
    testing::write_text(dir / name, text);
    try {
      core::read_mesh(dir / name, {}, 5);
      ADD_FAILURE() << name << " was accepted";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.code(), core::ExitCode::bad_input) << name << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find(name + "' (frame 5)"), std::string::npos) << e.what();
    }
  }
}

TEST(MeshPrecheck, BinaryNanAndCorruptListAreBadInput) {
  testing::TemporaryDirectory dir("mesh_precheck_binary");
  core::Mesh mesh = testing::make_sphere(4, 6);
  core::write_mesh(dir / "ok.ply", mesh);
  std::string bytes = core::read_file(dir / "ok.ply");
  const std::size_t body = bytes.find("end_header\n") + 11;
  std::string with_nan = bytes;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(with_nan.data() + body + 12, &nan, 4);  // vertex 1, x
  testing::write_text(dir / "nan.ply", with_nan);
  EXPECT_THROW(core::read_mesh(dir / "nan.ply"), core::Error);
  const std::size_t faces = body + static_cast<std::size_t>(mesh.vertex_count()) * 12;
  std::string corrupt = bytes;
  corrupt[faces] = static_cast<char>(250);  // first face claims 250 vertices
  testing::write_text(dir / "corrupt.ply", corrupt);
  EXPECT_THROW(core::read_mesh(dir / "corrupt.ply"), core::Error);
}

}  // namespace
}  // namespace surfcap
