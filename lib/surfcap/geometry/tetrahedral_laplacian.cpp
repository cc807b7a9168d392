#include "surfcap/geometry/tetrahedral_laplacian.hpp"

#ifndef TETLIBRARY
#define TETLIBRARY
#endif
#include <tetgen.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/geometry/mean_edge_length.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::geometry {

namespace {

/// Inside test by the sign of the offset from the closest surface point along the surface's
/// angle-weighted pseudo-normal there (Bærentzen & Aanæs 2005): the face's normal inside a face,
/// the sum of its two faces' normals on an edge, the angle-weighted normal at a vertex. Unlike the
/// closest face's normal alone, it is right at convex corners (a fingertip, a heel) for every
/// point of space, not only close to the surface, on a closed, consistently oriented surface that
/// does not pass through itself (where a reconstruction folds, it can still err).
class InsideTest {
 public:
  InsideTest(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) : surface_(V, F), F_(F) {
    vertex_normals_ = Eigen::MatrixXd::Zero(V.rows(), 3);
    edges_.reserve(static_cast<std::size_t>(3 * F.rows()));
    for (long f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d n = surface_.face_normal(f);
      for (int k = 0; k < 3; ++k) {
        const int a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
        const Eigen::Vector3d u = (V.row(b) - V.row(a)).transpose(), w = (V.row(c) - V.row(a)).transpose();
        const double nu = u.norm(), nw = w.norm();
        if (nu > 0 && nw > 0) vertex_normals_.row(a) += std::acos(std::clamp(u.dot(w) / (nu * nw), -1.0, 1.0)) * n;
        edges_.push_back({std::min(a, b), std::max(a, b), f});
      }
    }
    std::sort(edges_.begin(), edges_.end());
  }

  /// Is p inside? `distance` (if given) receives its distance from the surface.
  bool operator()(const Eigen::Vector3d& p, double* distance = nullptr) const {
    const SurfacePoint closest = surface_.closest_point(p);
    if (distance) *distance = closest.distance;
    return (p - closest.position).dot(pseudo_normal(closest)) < 0;
  }

 private:
  struct Edge {
    int a, b;
    long face;
    bool operator<(const Edge& o) const { return std::tie(a, b, face) < std::tie(o.a, o.b, o.face); }
  };

  Eigen::Vector3d pseudo_normal(const SurfacePoint& point) const {
    constexpr double kOnFeature = 1e-9;
    const Eigen::Vector3d& w = point.barycentric;
    int zeros = 0;
    for (int k = 0; k < 3; ++k) zeros += w(k) < kOnFeature;
    if (zeros == 0) return surface_.face_normal(point.face);
    if (zeros >= 2) {
      int corner = 0;
      w.maxCoeff(&corner);
      return vertex_normals_.row(F_(point.face, corner)).transpose();
    }
    int a = -1, b = -1;
    for (int k = 0; k < 3; ++k)
      if (w(k) >= kOnFeature) (a < 0 ? a : b) = F_(point.face, k);
    if (a > b) std::swap(a, b);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (auto it = std::lower_bound(edges_.begin(), edges_.end(), Edge{a, b, -1});
         it != edges_.end() && it->a == a && it->b == b; ++it)
      normal += surface_.face_normal(it->face);
    return normal;
  }

  SurfaceQuery surface_;
  Eigen::MatrixXi F_;
  Eigen::MatrixXd vertex_normals_;
  std::vector<Edge> edges_;
};

}  // namespace

TetMesh tetrahedralise(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const TetrahedraliseOptions& options) {
  const InsideTest inside(V, F);
  const double edge = mean_edge_length(V, F);
  std::vector<Eigen::Vector3d> interior;
  if (options.interior_spacing_edges > 0 && edge > 0) {
    const double spacing = options.interior_spacing_edges * edge;
    const Eigen::RowVector3d low = V.colwise().minCoeff(), high = V.colwise().maxCoeff();
    for (double x = low.x() + spacing / 2; x < high.x(); x += spacing)
      for (double y = low.y() + spacing / 2; y < high.y(); y += spacing)
        for (double z = low.z() + spacing / 2; z < high.z(); z += spacing) {
          double distance = 0;
          const Eigen::Vector3d p(x, y, z);
          if (inside(p, &distance) && distance > 0.5 * spacing) interior.push_back(p);
        }
  }
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(V.rows() + static_cast<long>(interior.size()));
  in.pointlist = new REAL[static_cast<std::size_t>(in.numberofpoints) * 3];
  for (long i = 0; i < V.rows(); ++i)
    for (int c = 0; c < 3; ++c) in.pointlist[i * 3 + c] = V(i, c);
  for (std::size_t k = 0; k < interior.size(); ++k)
    for (int c = 0; c < 3; ++c) in.pointlist[(static_cast<std::size_t>(V.rows()) + k) * 3 + c] = interior[k](c);
  char flags[] = "Q";  // Delaunay tetrahedralisation of the points, quiet
  try {
    tetrahedralize(flags, &in, &out);
  } catch (int code) {
    throw core::internal_error("TetGen failed (code " + std::to_string(code) + ")");
  }
  if (out.numberoftetrahedra <= 0 || out.numberofpoints != in.numberofpoints)
    throw core::internal_error("TetGen produced no tetrahedra or changed the points (duplicate vertices?)");
  TetMesh mesh;
  mesh.surface_vertices = V.rows();
  mesh.V.resize(out.numberofpoints, 3);
  for (int i = 0; i < out.numberofpoints; ++i)
    for (int c = 0; c < 3; ++c) mesh.V(i, c) = out.pointlist[i * 3 + c];
  mesh.V.topRows(V.rows()) = V;
  std::vector<Eigen::Vector4i> kept;
  const double min_volume = 1e-4 * edge * edge * edge;
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    Eigen::Vector4i tet;
    for (int c = 0; c < 4; ++c) tet(c) = out.tetrahedronlist[t * out.numberofcorners + c];
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int c = 0; c < 4; ++c) centroid += mesh.V.row(tet(c)).transpose() / 4.0;
    const Eigen::Vector3d p0 = mesh.V.row(tet(0)), p1 = mesh.V.row(tet(1)), p2 = mesh.V.row(tet(2)),
                          p3 = mesh.V.row(tet(3));
    const double volume = (p1 - p0).dot((p2 - p0).cross(p3 - p0)) / 6.0;
    if (volume < 0) std::swap(tet(2), tet(3));
    if (std::abs(volume) < min_volume || !inside(centroid)) continue;
    kept.push_back(tet);
  }
  mesh.T.resize(static_cast<long>(kept.size()), 4);
  for (std::size_t t = 0; t < kept.size(); ++t) mesh.T.row(static_cast<long>(t)) = kept[t].transpose();
  return mesh;
}

Eigen::VectorXd tet_volumes(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T) {
  Eigen::VectorXd volumes(T.rows());
  for (long t = 0; t < T.rows(); ++t) {
    const Eigen::Vector3d p0 = V.row(T(t, 0));
    const Eigen::Vector3d a = V.row(T(t, 1)).transpose() - p0, b = V.row(T(t, 2)).transpose() - p0,
                          c = V.row(T(t, 3)).transpose() - p0;
    volumes(t) = a.dot(b.cross(c)) / 6.0;
  }
  return volumes;
}

Eigen::SparseMatrix<double> tetrahedral_gradient_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(T.rows()) * 12);
  for (long t = 0; t < T.rows(); ++t) {
    Eigen::Matrix3d E;
    for (int k = 0; k < 3; ++k) E.col(k) = (V.row(T(t, k + 1)) - V.row(T(t, 0))).transpose();
    if (std::abs(E.determinant()) / 6.0 < 1e-18) continue;
    // Eᵀ ∇f = (f_k − f_0)_k  ⇒  ∇f = E⁻ᵀ (f_k − f_0).
    const Eigen::Matrix3d inverse_transpose = E.inverse().transpose();
    for (int axis = 0; axis < 3; ++axis) {
      double first = 0;
      for (int k = 0; k < 3; ++k) {
        triplets.emplace_back(3 * t + axis, T(t, k + 1), inverse_transpose(axis, k));
        first -= inverse_transpose(axis, k);
      }
      triplets.emplace_back(3 * t + axis, T(t, 0), first);
    }
  }
  Eigen::SparseMatrix<double> G(3 * T.rows(), V.rows());
  G.setFromTriplets(triplets.begin(), triplets.end());
  return G;
}

Eigen::SparseMatrix<double> tetrahedral_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T) {
  const Eigen::SparseMatrix<double> G = tetrahedral_gradient_operator(V, T);
  const Eigen::VectorXd volumes = tet_volumes(V, T).cwiseAbs();
  Eigen::VectorXd weights(3 * T.rows());
  for (long t = 0; t < T.rows(); ++t) weights.segment<3>(3 * t).setConstant(volumes(t));
  const Eigen::SparseMatrix<double> L = G.transpose() * weights.asDiagonal() * G;
  return L;
}

}  // namespace surfcap::geometry
