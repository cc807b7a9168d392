#include "surfcap/core/mesh.hpp"

#include <Eigen/Geometry>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "surfcap/core/error.hpp"

namespace surfcap::core {
namespace {

/// Directed edge (a→b) keyed so both directions of one undirected edge sort together.
struct EdgeUse {
  std::uint64_t key;  // min(a,b) << 32 | max(a,b)
  bool forward;       // a < b
  long face;
  bool operator<(const EdgeUse& other) const {
    return key != other.key ? key < other.key : (forward != other.forward ? forward < other.forward : face < other.face);
  }
};

void count_edge_problems(const Eigen::MatrixXi& F, const std::vector<char>& face_ok, MeshCheck& check) {
  std::vector<EdgeUse> uses;
  uses.reserve(static_cast<std::size_t>(F.rows()) * 3);
  for (long f = 0; f < F.rows(); ++f) {
    if (!face_ok[static_cast<std::size_t>(f)]) continue;
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint32_t>(F(f, k)), b = static_cast<std::uint32_t>(F(f, (k + 1) % 3));
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      uses.push_back({key, a < b, f});
    }
  }
  std::sort(uses.begin(), uses.end());
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    const std::size_t count = j - i;
    if (count == 1) {
      ++check.boundary_edges;
    } else if (count > 2 || uses[i].forward == uses[i + 1].forward) {
      // Three or more faces on one edge, or two faces with inconsistent orientation.
      ++check.non_manifold_edges;
      if (check.first_non_manifold_edge_face < 0) check.first_non_manifold_edge_face = uses[i].face;
    }
    i = j;
  }
}

}  // namespace

std::string MeshCheck::summary() const {
  std::string text;
  auto add = [&](long count, const std::string& what, long first, const std::string& unit) {
    if (count == 0) return;
    if (!text.empty()) text += ", ";
    text += std::to_string(count) + " " + what;
    if (first >= 0) text += " (first at " + unit + " " + std::to_string(first) + ")";
  };
  if (vertices == 0 || faces == 0) text = "empty mesh (" + std::to_string(vertices) + " vertices, " +
                                          std::to_string(faces) + " faces)";
  add(non_finite_vertices, "vertices with NaN/Inf coordinates", first_non_finite_vertex, "vertex");
  add(out_of_range_faces, "faces with out-of-range vertex indices", first_bad_face, "face");
  add(repeated_index_faces, "degenerate faces repeating a vertex", first_bad_face, "face");
  add(zero_area_faces, "zero-area faces", first_zero_area_face, "face");
  add(non_manifold_edges, "non-manifold edges", first_non_manifold_edge_face, "face");
  add(boundary_edges, "boundary edges", -1, "");
  add(unreferenced_vertices, "unreferenced vertices", -1, "");
  return text.empty() ? "ok" : text;
}

MeshCheck check_mesh(const Mesh& mesh, double area_tolerance) {
  MeshCheck check;
  const auto& V = mesh.V;
  const auto& F = mesh.F;
  check.vertices = V.rows();
  check.faces = F.rows();
  for (long v = 0; v < V.rows(); ++v) {
    if (!V.row(v).allFinite()) {
      if (check.first_non_finite_vertex < 0) check.first_non_finite_vertex = v;
      ++check.non_finite_vertices;
    }
  }
  std::vector<char> face_ok(static_cast<std::size_t>(F.rows()), 0);
  std::vector<char> referenced(static_cast<std::size_t>(V.rows()), 0);
  for (long f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (std::min({a, b, c}) < 0 || std::max({a, b, c}) >= V.rows()) {
      ++check.out_of_range_faces;
      if (check.first_bad_face < 0) check.first_bad_face = f;
      continue;
    }
    referenced[a] = referenced[b] = referenced[c] = 1;
    if (a == b || b == c || a == c) {
      ++check.repeated_index_faces;
      if (check.first_bad_face < 0) check.first_bad_face = f;
      continue;
    }
    face_ok[static_cast<std::size_t>(f)] = 1;
    const Eigen::Vector3d e1 = V.row(b) - V.row(a), e2 = V.row(c) - V.row(a);
    const double area = 0.5 * e1.cross(e2).norm();
    if (!(area >= area_tolerance) && V.row(a).allFinite() && V.row(b).allFinite() && V.row(c).allFinite()) {
      ++check.zero_area_faces;
      if (check.first_zero_area_face < 0) check.first_zero_area_face = f;
    }
  }
  check.unreferenced_vertices = std::count(referenced.begin(), referenced.end(), 0);
  count_edge_problems(F, face_ok, check);
  return check;
}

MeshCheck validate_mesh(const Mesh& mesh, const MeshRequirements& requirements,
                        const std::filesystem::path& source, std::optional<long> frame) {
  const MeshCheck check = check_mesh(mesh);
  auto fail = [&](const std::string& what) { throw bad_input(source, what, frame); };
  if (check.vertices == 0 || check.faces == 0) fail(check.summary());
  if (mesh.F.cols() != 3) fail("faces must be triangles");
  if (check.non_finite_vertices > 0)
    fail(std::to_string(check.non_finite_vertices) + " vertices have NaN/Inf coordinates (first: vertex " +
         std::to_string(check.first_non_finite_vertex) + ")");
  if (check.out_of_range_faces > 0)
    fail(std::to_string(check.out_of_range_faces) + " faces have vertex indices outside 0.." +
         std::to_string(check.vertices - 1) + " (first: face " + std::to_string(check.first_bad_face) + ")");
  if (check.repeated_index_faces > 0)
    fail(std::to_string(check.repeated_index_faces) + " degenerate faces use one vertex twice (first: face " +
         std::to_string(check.first_bad_face) + ")");
  if (check.zero_area_faces > 0 && !requirements.allow_zero_area_faces)
    fail(std::to_string(check.zero_area_faces) + " zero-area faces (first: face " +
         std::to_string(check.first_zero_area_face) + ")");
  if (check.non_manifold_edges > 0 && !requirements.allow_non_manifold)
    fail(std::to_string(check.non_manifold_edges) + " non-manifold edges (first at face " +
         std::to_string(check.first_non_manifold_edge_face) + ")");
  if (check.boundary_edges > 0 && !requirements.allow_open)
    fail("the surface is open: " + std::to_string(check.boundary_edges) + " boundary edges");
  if (requirements.require_colors && !mesh.has_colors()) fail("the mesh has no per-vertex colours");
  // An open surface is what a studio reconstruction cut at the floor is: data, not a defect.
  if (check.zero_area_faces + check.non_manifold_edges + check.unreferenced_vertices > 0)
    spdlog::warn("{}: {}", where(source, frame), check.summary());
  else if (check.boundary_edges > 0)
    spdlog::debug("{}: {}", where(source, frame), check.summary());
  return check;
}

Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd areas(F.rows());
  for (long f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d e1 = V.row(F(f, 1)) - V.row(F(f, 0)), e2 = V.row(F(f, 2)) - V.row(F(f, 0));
    areas(f) = 0.5 * e1.cross(e2).norm();
  }
  return areas;
}

Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(V.rows(), 3);
  for (long f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d e1 = V.row(F(f, 1)) - V.row(F(f, 0)), e2 = V.row(F(f, 2)) - V.row(F(f, 0));
    const Eigen::RowVector3d weighted = e1.cross(e2).transpose();  // |n| = 2 × area
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += weighted;
  }
  for (long v = 0; v < N.rows(); ++v) {
    const double length = N.row(v).norm();
    if (length > 0) N.row(v) /= length;
  }
  return N;
}

double bounding_box_diagonal(const Eigen::MatrixXd& V) {
  if (V.rows() == 0) return 0.0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

}  // namespace surfcap::core
