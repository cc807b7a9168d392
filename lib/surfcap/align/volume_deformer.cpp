#include "surfcap/align/volume_deformer.hpp"

#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <Eigen/SVD>

#include "surfcap/core/error.hpp"
#include "surfcap/geometry/best_rotation.hpp"
#include "surfcap/geometry/gradient_operator.hpp"
#include "surfcap/geometry/mesh_topology.hpp"
#include "surfcap/geometry/vertex_grid.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>

namespace surfcap::align {

namespace {

/// The tets that join two parts of the surface touching at rest — a hand on the hip, thighs
/// pressed together, an arm a visual hull fused to the torso: parts close in space but far apart
/// along the surface. Each tet vertex is labelled with its surface vertex (a surface vertex
/// itself; an interior point, the nearest surface vertex within `kLabelEdges` mean edges, else
/// none); a tet glues when two of its labels lie within `kNearEdges` edges of each other in space
/// but farther apart along the surface's edges than `kDetour` times that and than `kFarHeight` of
/// the template's height. The path from a limb to the body part it rests on runs through a joint
/// (a hand on the hip: up the arm and down the torso), a sizeable part of the body; shorter
/// detours are a garment's fold or a blob fused to the surface, which move with what they touch.
/// `contacts` receives the surface vertices, sorted, whose pairs make the cut tets glue.
std::vector<char> gluing_tets(const Eigen::MatrixXd& rest, long surface_vertices, const Eigen::MatrixXi& F,
                              const Eigen::MatrixXi& T, double edge, std::vector<long>& contacts) {
  constexpr double kLabelEdges = 3.0, kNearEdges = 4.0, kDetour = 4.0, kFarHeight = 1.0 / 3.0;
  const auto up = rest.topRows(surface_vertices).col(1);
  const double height = up.maxCoeff() - up.minCoeff();
  const long n = rest.rows();
  std::vector<long> label(static_cast<std::size_t>(n), -1);
  for (long v = 0; v < surface_vertices; ++v) label[static_cast<std::size_t>(v)] = v;
  if (n > surface_vertices) {
    const Eigen::MatrixXd surface = rest.topRows(surface_vertices);
    const geometry::VertexGrid grid(surface, kLabelEdges * edge);
    for (long v = surface_vertices; v < n; ++v) {
      double best = kLabelEdges * edge;
      grid.around(rest.row(v).transpose(), [&](long s) {
        const double d = (surface.row(s) - rest.row(v)).norm();
        if (d < best || (d == best && s < label[static_cast<std::size_t>(v)])) {
          best = d;
          label[static_cast<std::size_t>(v)] = s;
        }
      });
    }
  }
  // Calls visit(a, b) for each pair of distinct labels a < b of tet t's vertices.
  const auto for_label_pairs = [&](long t, const auto& visit) {
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const long a = label[static_cast<std::size_t>(T(t, i))], b = label[static_cast<std::size_t>(T(t, j))];
        if (a >= 0 && b >= 0 && a != b) visit(std::min(a, b), std::max(a, b));
      }
  };
  // Pairs of labels to test, grouped by their lower label.
  std::vector<std::vector<long>> partners(static_cast<std::size_t>(surface_vertices));
  const double near = kNearEdges * edge;
  for (long t = 0; t < T.rows(); ++t)
    for_label_pairs(t, [&](long a, long b) {
      if ((rest.row(a) - rest.row(b)).norm() <= near) partners[static_cast<std::size_t>(a)].push_back(b);
    });
  const auto adjacency = geometry::vertex_adjacency(F, surface_vertices);
  const double far_along = kFarHeight * height, radius = std::max(kDetour * near, far_along);
  std::vector<double> distance(static_cast<std::size_t>(surface_vertices), std::numeric_limits<double>::infinity());
  std::vector<long> touched;
  std::vector<std::vector<long>> far(static_cast<std::size_t>(surface_vertices));
  using Entry = std::pair<double, long>;
  for (long a = 0; a < surface_vertices; ++a) {
    auto& list = partners[static_cast<std::size_t>(a)];
    if (list.empty()) continue;
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    // Dijkstra along the edges from a, up to `radius` or until every partner is settled (most
    // are a few edges away): one small search per vertex in one reused buffer, where
    // geometry::edge_geodesic_distance would sweep the whole mesh each time.
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    distance[static_cast<std::size_t>(a)] = 0;
    touched.push_back(a);
    queue.emplace(0.0, a);
    std::size_t settled = 0;
    while (!queue.empty() && settled < list.size()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > distance[static_cast<std::size_t>(v)]) continue;  // only entries within `radius` are queued
      if (std::binary_search(list.begin(), list.end(), v)) ++settled;
      for (const int u : adjacency[static_cast<std::size_t>(v)]) {
        const double next = d + (rest.row(v) - rest.row(u)).norm();
        if (next < distance[static_cast<std::size_t>(u)] && next <= radius) {
          if (!std::isfinite(distance[static_cast<std::size_t>(u)])) touched.push_back(u);
          distance[static_cast<std::size_t>(u)] = next;
          queue.emplace(next, u);
        }
      }
    }
    for (const long b : list) {
      const double apart = (rest.row(a) - rest.row(b)).norm();
      if (distance[static_cast<std::size_t>(b)] > std::max(kDetour * apart, far_along))
        far[static_cast<std::size_t>(a)].push_back(b);
    }
    for (const long v : touched) distance[static_cast<std::size_t>(v)] = std::numeric_limits<double>::infinity();
    touched.clear();
  }
  std::vector<char> gluing(static_cast<std::size_t>(T.rows()), 0);
  contacts.clear();
  for (long t = 0; t < T.rows(); ++t)
    for_label_pairs(t, [&](long a, long b) {
      const auto& list = far[static_cast<std::size_t>(a)];
      if (std::binary_search(list.begin(), list.end(), b)) {
        gluing[static_cast<std::size_t>(t)] = 1;
        contacts.push_back(a);
        contacts.push_back(b);
      }
    });
  std::sort(contacts.begin(), contacts.end());
  contacts.erase(std::unique(contacts.begin(), contacts.end()), contacts.end());
  return gluing;
}

}  // namespace

VolumeDeformer::VolumeDeformer(const core::Mesh& template_mesh, const DeformerOptions& options,
                               const std::vector<char>& unseen) {
  surface_vertices_ = template_mesh.vertex_count();
  if (!unseen.empty() && static_cast<long>(unseen.size()) != surface_vertices_)
    throw core::internal_error("VolumeDeformer: one unseen flag per template vertex");
  std::string fallback_reason = "volumetric model disabled";
  const Eigen::SparseMatrix<double> surface_gradient = geometry::gradient_operator(template_mesh.V, template_mesh.F);
  const Eigen::VectorXd areas = core::face_areas(template_mesh.V, template_mesh.F);
  // The mean length of one edge per face: the thickness of the surface shells and the scale of the
  // gluing test.
  double edge = 0;
  for (long f = 0; f < template_mesh.F.rows(); ++f)
    edge += (template_mesh.V.row(template_mesh.F(f, 0)) - template_mesh.V.row(template_mesh.F(f, 1))).norm();
  edge /= std::max<double>(1.0, static_cast<double>(template_mesh.F.rows()));
  if (!options.surface_model) {
    try {
      const geometry::TetMesh tets = geometry::tetrahedralise(template_mesh.V, template_mesh.F, options.tetrahedra);
      rest_ = tets.V;
      tetrahedra_ = tets.T;
      // Tets plus the surface triangles (as thin shells of half an edge): every surface vertex
      // stays attached even where a tet was carved away (gaps, self-intersections).
      const Eigen::SparseMatrix<double> tet_gradient = geometry::tetrahedral_gradient_operator(rest_, tetrahedra_);
      std::vector<Eigen::Triplet<double>> triplets;
      for (int k = 0; k < tet_gradient.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator it(tet_gradient, k); it; ++it)
          triplets.emplace_back(it.row(), it.col(), it.value());
      for (int k = 0; k < surface_gradient.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator it(surface_gradient, k); it; ++it)
          triplets.emplace_back(tet_gradient.rows() + it.row(), it.col(), it.value());
      G_.resize(tet_gradient.rows() + surface_gradient.rows(), rest_.rows());
      G_.setFromTriplets(triplets.begin(), triplets.end());
      element_weights_.resize(tetrahedra_.rows() + areas.size());
      element_weights_ << geometry::tet_volumes(rest_, tetrahedra_).cwiseAbs(), areas * (0.5 * edge);
      model_ = "tetrahedral";
    } catch (const core::Error& error) {
      fallback_reason = error.what();
      spdlog::warn("template tetrahedralisation failed ({}); using the surface deformation model", error.what());
    }
  }
  if (model_.empty()) {
    rest_ = template_mesh.V;
    G_ = surface_gradient;
    element_weights_ = areas;
    model_ = "surface (" + fallback_reason + ")";
  }
  const long elements = element_weights_.size();
  const auto diagonal_of = [&] {
    Eigen::VectorXd D(3 * elements);
    for (long e = 0; e < elements; ++e) D.segment<3>(3 * e).setConstant(element_weights_(e));
    return D;
  };
  Eigen::VectorXd D = diagonal_of();
  Eigen::SparseMatrix<double> L = G_.transpose() * D.asDiagonal() * G_;
  double diagonal = 0;
  for (long i = 0; i < surface_vertices_; ++i) diagonal += L.coeff(i, i);
  scale_ = diagonal > 0 ? diagonal / static_cast<double>(surface_vertices_) : 1.0;
  if (tetrahedra_.rows() > 0) {
    const std::vector<char> gluing =
        gluing_tets(rest_, surface_vertices_, template_mesh.F, tetrahedra_, edge, cut_vertices_);
    for (long e = 0; e < tetrahedra_.rows(); ++e)
      if (gluing[static_cast<std::size_t>(e)]) {
        element_weights_(e) = 0;
        ++cut_elements_;
      }
  }
  if (!unseen.empty() || cut_elements_ > 0) {
    for (long e = 0; e < tetrahedra_.rows() && !unseen.empty(); ++e) {
      bool on_surface = false, all_unseen = true;
      for (int k = 0; k < 4; ++k) {
        const int v = tetrahedra_(e, k);
        if (v >= surface_vertices_) continue;
        on_surface = true;
        all_unseen = all_unseen && unseen[static_cast<std::size_t>(v)];
      }
      if (on_surface && all_unseen) {
        element_weights_(e) *= kUnseenRigidity;
        ++softened_elements_;
      }
    }
    if (softened_elements_ > 0 || cut_elements_ > 0) {
      D = diagonal_of();
      L = G_.transpose() * D.asDiagonal() * G_;
    }
  }
  L_ = L / scale_;
  GtD_ = Eigen::SparseMatrix<double>(G_.transpose() * D.asDiagonal()) / scale_;
  rest_gradients_ = G_ * rest_;
}

geometry::SparseCholesky VolumeDeformer::factor(const Eigen::VectorXd& weights) const {
  return geometry::SparseCholesky(system(weights));
}

void VolumeDeformer::factor(const Eigen::VectorXd& weights, geometry::SparseCholesky& solver) const {
  solver.refactor(system(weights));
}

Eigen::SparseMatrix<double> VolumeDeformer::system(const Eigen::VectorXd& weights) const {
  if (weights.size() != surface_vertices_) throw core::internal_error("VolumeDeformer::factor: weight count");
  if (!(weights.array() >= 0).all() || weights.maxCoeff() <= 0)
    throw core::internal_error("VolumeDeformer::factor: weights must be ≥ 0 with one positive");
  Eigen::SparseMatrix<double> A = L_;
  for (long i = 0; i < surface_vertices_; ++i)
    if (weights(i) > 0) A.coeffRef(i, i) += weights(i);
  // Interior-only components (none for a connected tet mesh) would be singular: a tiny
  // regulariser keeps the factorisation positive definite without biasing the result.
  for (long i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += 1e-9;
  A.makeCompressed();
  return A;
}

Eigen::MatrixXd VolumeDeformer::rotated_gradients(const Eigen::MatrixXd& positions) const {
  const Eigen::MatrixXd gradients = G_ * positions;  // 3E×3: rows of element e hold ∂x_c/∂p_axis
  Eigen::MatrixXd rotated(gradients.rows(), 3);
  for (long e = 0; e < element_weights_.size(); ++e) {
    const Eigen::Matrix3d A = rest_gradients_.block<3, 3>(3 * e, 0);
    const Eigen::Matrix3d B = gradients.block<3, 3>(3 * e, 0);
    rotated.block<3, 3>(3 * e, 0) = A * geometry::best_rotation(A.transpose() * B);
  }
  return rotated;
}

Eigen::MatrixXd VolumeDeformer::deform(const geometry::SparseCholesky& solver, const Eigen::MatrixXd& initial,
                                       const Eigen::MatrixXd& targets, const Eigen::VectorXd& weights,
                                       int iterations) const {
  if (initial.rows() != vertex_count() || targets.rows() != surface_vertices_)
    throw core::internal_error("VolumeDeformer::deform: position counts");
  Eigen::MatrixXd constraint_rhs = Eigen::MatrixXd::Zero(vertex_count(), 3);
  constraint_rhs.topRows(surface_vertices_) = weights.asDiagonal() * targets;
  Eigen::MatrixXd positions = initial;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const Eigen::MatrixXd rhs = GtD_ * rotated_gradients(positions) + constraint_rhs;
    positions = solver.solve(rhs);
  }
  return positions;
}

double VolumeDeformer::rigidity_energy(const Eigen::MatrixXd& positions) const {
  const Eigen::MatrixXd difference = G_ * positions - rotated_gradients(positions);
  double energy = 0;
  for (long e = 0; e < element_weights_.size(); ++e)
    energy += element_weights_(e) * difference.block<3, 3>(3 * e, 0).squaredNorm();
  return energy / scale_;
}

}  // namespace surfcap::align
