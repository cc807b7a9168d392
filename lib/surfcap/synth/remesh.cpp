#include "surfcap/synth/remesh.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <random>

#include "surfcap/core/error.hpp"
#include "surfcap/core/surface_mesh_copy.hpp"
#include "surfcap/geometry/mean_edge_length.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::synth {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Uniform doubles in [0, 1) from the top 53 bits: the same on every platform (unlike std:: distributions).
double uniform(std::mt19937_64& engine) { return static_cast<double>(engine() >> 11) * (1.0 / 9007199254740992.0); }
double gaussian(std::mt19937_64& engine) {
  const double u1 = uniform(engine) + 0.5 / 9007199254740992.0, u2 = uniform(engine);
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
}

}  // namespace

RemeshResult remesh(const core::Mesh& source, const RemeshOptions& options) {
  std::mt19937_64 engine(options.seed);
  const double edge = options.edge * (1.0 + options.edge_jitter * (2 * uniform(engine) - 1));
  // A seeded tangential perturbation so two frames with the same geometry still remesh differently.
  const Eigen::MatrixXd normals = core::vertex_normals(source.V, source.F);
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::Vertex_index> vertices;
  for (long v = 0; v < source.vertex_count(); ++v) {
    Eigen::Vector3d offset(gaussian(engine), gaussian(engine), gaussian(engine));
    const Eigen::Vector3d n = normals.row(v).transpose();
    offset -= n * n.dot(offset);
    const Eigen::Vector3d p = source.V.row(v).transpose() + options.tangential_jitter * geometry::mean_edge_length(source.V, source.F) * 0.3 * offset;
    vertices.push_back(mesh.add_vertex(Point(p.x(), p.y(), p.z())));
  }
  for (long f = 0; f < source.face_count(); ++f)
    if (mesh.add_face(vertices[source.F(f, 0)], vertices[source.F(f, 1)], vertices[source.F(f, 2)]) ==
        SurfaceMesh::null_face())
      throw core::internal_error("remesh: the surface is not manifold at face " + std::to_string(f));
  PMP::isotropic_remeshing(faces(mesh), edge, mesh, PMP::parameters::number_of_iterations(options.iterations));

  RemeshResult result;
  result.mesh = core::copy_surface_mesh(mesh);
  core::Mesh& out = result.mesh;
  // Snap onto the (unperturbed) source surface and record where each vertex lies on it.
  const geometry::SurfaceQuery query(source.V, source.F);
  result.face.resize(static_cast<std::size_t>(out.V.rows()));
  result.barycentric.resize(out.V.rows(), 3);
  for (long v = 0; v < out.V.rows(); ++v) {
    const geometry::SurfacePoint closest = query.closest_point(out.V.row(v).transpose());
    Eigen::Vector3d b = closest.barycentric.cwiseMax(0.0);
    b /= b.sum();
    result.face[static_cast<std::size_t>(v)] = static_cast<int>(closest.face);
    result.barycentric.row(v) = b.transpose();
    out.V.row(v) = b(0) * source.V.row(source.F(closest.face, 0)) + b(1) * source.V.row(source.F(closest.face, 1)) +
                   b(2) * source.V.row(source.F(closest.face, 2));
  }
  if (options.noise_sigma > 0) {
    const Eigen::MatrixXd new_normals = core::vertex_normals(out.V, out.F);
    for (long v = 0; v < out.V.rows(); ++v) out.V.row(v) += options.noise_sigma * gaussian(engine) * new_normals.row(v);
  }
  return result;
}

}  // namespace surfcap::synth
