#include "surfcap/align/volume_deformer.hpp"

#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <Eigen/SVD>

#include "surfcap/core/error.hpp"
#include "surfcap/geometry/best_rotation.hpp"
#include "surfcap/geometry/gradient_operator.hpp"

namespace surfcap::align {

VolumeDeformer::VolumeDeformer(const core::Mesh& template_mesh, const DeformerOptions& options,
                               const std::vector<char>& unseen) {
  surface_vertices_ = template_mesh.vertex_count();
  if (!unseen.empty() && static_cast<long>(unseen.size()) != surface_vertices_)
    throw core::internal_error("VolumeDeformer: one unseen flag per template vertex");
  std::string fallback_reason = "volumetric model disabled";
  const Eigen::SparseMatrix<double> surface_gradient = geometry::gradient_operator(template_mesh.V, template_mesh.F);
  const Eigen::VectorXd areas = core::face_areas(template_mesh.V, template_mesh.F);
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
      double edge = 0;
      for (long f = 0; f < template_mesh.F.rows(); ++f)
        edge += (template_mesh.V.row(template_mesh.F(f, 0)) - template_mesh.V.row(template_mesh.F(f, 1))).norm();
      edge /= std::max<double>(1.0, static_cast<double>(template_mesh.F.rows()));
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
  if (!unseen.empty()) {
    for (long e = 0; e < tetrahedra_.rows(); ++e) {
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
    if (softened_elements_ > 0) {
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
