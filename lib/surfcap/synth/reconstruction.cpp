#include "surfcap/synth/reconstruction.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/random_perturbation.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <random>

#include "surfcap/core/error.hpp"
#include "surfcap/core/surface_mesh_copy.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::synth {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh to_surface_mesh(const core::Mesh& mesh) {
  SurfaceMesh result;
  std::vector<SurfaceMesh::Vertex_index> vertices;
  for (long v = 0; v < mesh.vertex_count(); ++v)
    vertices.push_back(result.add_vertex(Point(mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2))));
  for (long f = 0; f < mesh.face_count(); ++f)
    if (result.add_face(vertices[mesh.F(f, 0)], vertices[mesh.F(f, 1)], vertices[mesh.F(f, 2)]) ==
        SurfaceMesh::null_face())
      throw core::internal_error("reconstruct: the true surface is not manifold at face " + std::to_string(f));
  return result;
}

/// Barycentric coordinates of a point on the triangle, inside it despite rounding: ≥ 0, sum 1.
Eigen::Vector3d clamped(Eigen::Vector3d barycentric) {
  barycentric = barycentric.cwiseMax(0.0);
  const double sum = barycentric.sum();
  return sum > 0 ? Eigen::Vector3d(barycentric / sum) : Eigen::Vector3d(1, 0, 0);
}

}  // namespace

double mean_edge_length(const core::Mesh& mesh) {
  double sum = 0;
  for (long f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) sum += (mesh.V.row(mesh.F(f, k)) - mesh.V.row(mesh.F(f, (k + 1) % 3))).norm();
  return mesh.face_count() > 0 ? sum / (3.0 * mesh.face_count()) : 0.0;
}

Eigen::MatrixXd surface_points(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& face,
                               const Eigen::MatrixXd& barycentric) {
  Eigen::MatrixXd points(static_cast<long>(face.size()), 3);
  for (long i = 0; i < points.rows(); ++i) {
    const int f = face[static_cast<std::size_t>(i)];
    points.row(i) = barycentric(i, 0) * V.row(F(f, 0)) + barycentric(i, 1) * V.row(F(f, 1)) + barycentric(i, 2) * V.row(F(f, 2));
  }
  return points;
}

core::Mesh remesh_truth(const core::Mesh& truth, double edge, std::uint64_t seed, const ReconstructionOptions& options,
                        double& target_edge) {
  std::mt19937_64 engine(seed);
  const double u = static_cast<double>(engine() >> 11) * (1.0 / 9007199254740992.0);
  target_edge = edge * (1.0 + options.edge_jitter * (2 * u - 1));

  SurfaceMesh mesh = to_surface_mesh(truth);
  PMP::random_perturbation(mesh, 0.3 * edge,
                           PMP::parameters::random_seed(static_cast<unsigned>(engine() & 0x7fffffff)).do_project(true));
  PMP::isotropic_remeshing(faces(mesh), target_edge, mesh, PMP::parameters::number_of_iterations(options.iterations));
  return core::copy_surface_mesh(mesh);
}

core::Mesh remesh_surface(const core::Mesh& input, double edge, int iterations) {
  SurfaceMesh mesh = to_surface_mesh(input);
  PMP::isotropic_remeshing(faces(mesh), edge, mesh, PMP::parameters::number_of_iterations(iterations));
  return core::copy_surface_mesh(mesh);
}

void closest_truth_points(const core::Mesh& truth, const Eigen::MatrixXd& points, std::vector<int>& face,
                          Eigen::MatrixXd& barycentric) {
  const geometry::SurfaceQuery query(truth.V, truth.F);
  const long n = points.rows();
  face.resize(static_cast<std::size_t>(n));
  barycentric.resize(n, 3);
  for (long v = 0; v < n; ++v) {
    const geometry::SurfacePoint closest = query.closest_point(points.row(v).transpose());
    face[static_cast<std::size_t>(v)] = static_cast<int>(closest.face);
    barycentric.row(v) = clamped(closest.barycentric).transpose();
  }
}

Reconstruction reconstruct(const core::Mesh& truth, double edge, std::uint64_t seed,
                           const ReconstructionOptions& options) {
  Reconstruction result;
  result.mesh = remesh_truth(truth, edge, seed, options, result.target_edge);
  const long n = result.mesh.vertex_count();
  closest_truth_points(truth, result.mesh.V, result.face, result.barycentric);
  // The reconstruction's noise-free vertices are exactly its true surface points.
  result.mesh.V = surface_points(truth.V, truth.F, result.face, result.barycentric);
  if (options.noise_sigma > 0) {
    const Eigen::MatrixXd normals = core::vertex_normals(result.mesh.V, result.mesh.F);
    Gaussian gaussian{std::mt19937_64(seed ^ 0x5eed5eed5eedULL)};
    for (long v = 0; v < n; ++v) result.mesh.V.row(v) += options.noise_sigma * gaussian.next() * normals.row(v);
  }
  return result;
}

}  // namespace surfcap::synth
