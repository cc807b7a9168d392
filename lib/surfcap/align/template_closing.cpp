#include "surfcap/align/template_closing.hpp"

#ifndef CGAL_EIGEN3_ENABLED
#define CGAL_EIGEN3_ENABLED  // the fairing's default sparse solver is Eigen's
#endif
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <iterator>
#include <limits>
#include <vector>

#include "surfcap/align/observed_surface.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/geometry/mesh_topology.hpp"

namespace surfcap::align {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;

SurfaceMesh surface_of(const core::Mesh& mesh) {
  SurfaceMesh surface;
  for (long v = 0; v < mesh.V.rows(); ++v) surface.add_vertex({mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2)});
  for (long f = 0; f < mesh.F.rows(); ++f) {
    const auto corner = [&](int k) { return VertexIndex(static_cast<SurfaceMesh::size_type>(mesh.F(f, k))); };
    if (surface.add_face(corner(0), corner(1), corner(2)) == SurfaceMesh::null_face())
      throw core::internal_error("close_template: the reconstruction is not edge-manifold");
  }
  return surface;
}

/// `mesh` without its small pieces (observed_surface.hpp: the child's side leaves them unobserved);
/// records them in `result`.
core::Mesh without_loose_pieces(core::Mesh mesh, TemplateSurface& result) {
  const long n = mesh.vertex_count();
  long small = 0;
  const Eigen::VectorXd shares = piece_shares(n, mesh.F, small, kSmallPieceShare);
  if (n == 0 || shares.maxCoeff() < kSmallPieceShare) return mesh;  // all in shards: none is the body
  result.loose_pieces = small;
  std::vector<int> kept;
  for (long v = 0; v < n; ++v) {
    if (shares(v) >= kSmallPieceShare) kept.push_back(static_cast<int>(v));
    else result.dropped_vertices.push_back(v);
  }
  if (result.dropped_vertices.empty()) return mesh;
  const geometry::Submesh sub = geometry::extract_submesh(mesh.F, n, kept);
  const auto rows = [&](const Eigen::MatrixXd& values) {
    Eigen::MatrixXd picked(static_cast<long>(kept.size()), values.cols());
    for (std::size_t i = 0; i < kept.size(); ++i) picked.row(static_cast<long>(i)) = values.row(kept[i]);
    return picked;
  };
  core::Mesh out;
  out.V = rows(mesh.V);
  if (mesh.has_colors()) out.colors = rows(mesh.colors);
  if (mesh.has_uvs()) out.uvs = rows(mesh.uvs);
  out.F = sub.F;
  return out;
}

/// The rim vertex nearest to `p` (for the new vertices' colours and texture coordinates).
long nearest_rim_vertex(const SurfaceMesh& surface, const std::vector<VertexIndex>& rim, const Kernel::Point_3& p) {
  long best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const VertexIndex v : rim) {
    const double d = CGAL::squared_distance(surface.point(v), p);
    if (d < best_distance) best_distance = d, best = static_cast<long>(v.idx());
  }
  return best;
}

}  // namespace

TemplateSurface close_template(core::Mesh input) {
  TemplateSurface result;
  core::Mesh reconstruction = without_loose_pieces(std::move(input), result);
  result.observed_vertices = reconstruction.vertex_count();
  result.observed_faces = reconstruction.face_count();
  SurfaceMesh surface = surface_of(reconstruction);
  std::vector<SurfaceMesh::Halfedge_index> holes;
  PMP::extract_boundary_cycles(surface, std::back_inserter(holes));
  if (holes.empty()) {
    result.mesh = std::move(reconstruction);
    return result;
  }
  // Per new vertex, the rim vertex it copies its colour and texture coordinates from.
  std::vector<long> source_of;
  for (const auto hole : holes) {
    std::vector<VertexIndex> rim;
    double perimeter = 0;
    for (const auto h : CGAL::halfedges_around_face(hole, surface)) {
      rim.push_back(surface.source(h));
      perimeter += std::sqrt(CGAL::squared_distance(surface.point(surface.source(h)), surface.point(surface.target(h))));
    }
    ++result.holes;
    result.largest_hole_perimeter = std::max(result.largest_hole_perimeter, perimeter);
    std::vector<SurfaceMesh::Face_index> faces;
    std::vector<VertexIndex> vertices;
    const auto filled = PMP::triangulate_refine_and_fair_hole(surface, hole, std::back_inserter(faces),
                                                               std::back_inserter(vertices),
                                                               CGAL::parameters::fairing_continuity(1));
    if (faces.empty()) throw core::internal_error("close_template: a hole of the root reconstruction could not be closed");
    if (!std::get<0>(filled)) ++result.unfaired_holes;
  }
  if (surface.has_garbage()) throw core::internal_error("close_template: hole filling removed elements");
  const long n = static_cast<long>(surface.number_of_vertices());
  source_of.assign(static_cast<std::size_t>(n - result.observed_vertices), -1);
  core::Mesh& mesh = result.mesh;
  mesh.V.resize(n, 3);
  mesh.V.topRows(result.observed_vertices) = reconstruction.V;
  for (long v = result.observed_vertices; v < n; ++v) {
    const auto& p = surface.point(VertexIndex(static_cast<SurfaceMesh::size_type>(v)));
    mesh.V.row(v) << p.x(), p.y(), p.z();
  }
  mesh.F.resize(static_cast<long>(surface.number_of_faces()), 3);
  for (const auto f : surface.faces()) {
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(surface.halfedge(f), surface))
      mesh.F(static_cast<long>(f.idx()), k++) = static_cast<int>(v.idx());
  }
  if (reconstruction.has_colors() || reconstruction.has_uvs()) {
    // Rim vertices: those of the original vertices on a closing face.
    std::vector<VertexIndex> rim;
    for (long f = result.observed_faces; f < mesh.F.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (mesh.F(f, k) < result.observed_vertices) rim.push_back(VertexIndex(static_cast<SurfaceMesh::size_type>(mesh.F(f, k))));
    std::sort(rim.begin(), rim.end());
    rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
    for (long v = result.observed_vertices; v < n; ++v)
      source_of[static_cast<std::size_t>(v - result.observed_vertices)] =
          nearest_rim_vertex(surface, rim, surface.point(VertexIndex(static_cast<SurfaceMesh::size_type>(v))));
    const auto extend = [&](const Eigen::MatrixXd& values) {
      Eigen::MatrixXd extended(n, values.cols());
      extended.topRows(result.observed_vertices) = values;
      for (long v = result.observed_vertices; v < n; ++v)
        extended.row(v) = values.row(source_of[static_cast<std::size_t>(v - result.observed_vertices)]);
      return extended;
    };
    if (reconstruction.has_colors()) mesh.colors = extend(reconstruction.colors);
    if (reconstruction.has_uvs()) mesh.uvs = extend(reconstruction.uvs);
  }
  if (result.unfaired_holes > 0)
    spdlog::warn("template: {} of its {} holes closed without fairing (the refined patch is kept)",
                 result.unfaired_holes, result.holes);
  return result;
}

}  // namespace surfcap::align
