#include "surfcap/learn/learnt_laplacian_space.hpp"

#include <Eigen/Eigenvalues>

#include "surfcap/core/error.hpp"

namespace surfcap::learn {
namespace {

// argmin_R Σ‖R a_j − b_j‖² for S = Σ a_j b_jᵀ: R = V Uᵀ with S = U Σ Vᵀ. The closed-form 3×3
// eigen-solver on SᵀS is ~10× faster than a Jacobi SVD; the third axis comes from a cross product,
// which also handles flat one-rings (rank-2 S) and reflections.
Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& S) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(S.transpose() * S);
  const Eigen::Vector3d values = eigen.eigenvalues();  // ascending
  if (!(values[1] > 1e-20 * std::max(1e-300, values[2]))) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d v1 = eigen.eigenvectors().col(2), v2 = eigen.eigenvectors().col(1);
  const Eigen::Vector3d u1 = (S * v1).normalized();
  const Eigen::Vector3d u2 = (S * v2 - (S * v2).dot(u1) * u1).normalized();
  Eigen::Matrix3d U, V;
  U << u1, u2, u1.cross(u2);
  V << v1, v2, v1.cross(v2);
  return V * U.transpose();
}

}  // namespace

LearntLaplacianSpace::LearntLaplacianSpace(Eigen::SparseMatrix<double> D, std::array<Eigen::MatrixXd, 3> basis,
                                           Eigen::MatrixXd g, Eigen::VectorXd r0, Eigen::MatrixXd reference,
                                           double regularisation, std::vector<std::vector<int>> rotation_adjacency)
    : D_(std::move(D)), E_(std::move(basis)), g_(std::move(g)), reference_(std::move(reference)), r0_(std::move(r0)),
      mu_(regularisation), adjacency_(std::move(rotation_adjacency)) {
  Dt_ = D_.transpose();
  DtD_ = Dt_ * D_;
  for (int c = 0; c < 3; ++c) U_[c] = Dt_ * E_[c];
  // A whisper of ε‖x − x_ref‖² keeps K definite where a piece of a part holds no constraint
  // (isolated vertices, disconnected bits); it changes nothing measurable elsewhere.
  tikhonov_ = 1e-8 * std::max(1e-12, DtD_.diagonal().mean());
  for (Eigen::Index i = 0; i < DtD_.rows(); ++i) DtD_.coeffRef(i, i) += tikhonov_;
  anchor_rhs_ = tikhonov_ * reference_;
  if (!adjacency_.empty() && basis_size() > 0) {
    // Shapes of basis directions, B = D⁺E (translation is irrelevant: only used for rotations).
    Eigen::SparseMatrix<double> A = DtD_;
    const double epsilon = 1e-6 * DtD_.diagonal().mean();
    for (Eigen::Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += epsilon;
    const geometry::SparseCholesky solver(A);
    for (int c = 0; c < 3; ++c) shape_basis_[c] = solver.solve(U_[c]);
  }
}

std::unique_ptr<LearntLaplacianSpace::Prepared> LearntLaplacianSpace::prepare(const std::vector<int>& vertices,
                                                                              const Eigen::VectorXd& weights) const {
  if (vertices.empty()) throw core::internal_error("LearntLaplacianSpace::prepare without constraints");
  auto prepared = std::make_unique<Prepared>();
  prepared->vertices = vertices;
  prepared->weights = weights;
  Eigen::SparseMatrix<double> K = DtD_;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    K.coeffRef(vertices[i], vertices[i]) += weights[static_cast<Eigen::Index>(i)] * weights[static_cast<Eigen::Index>(i)];
  prepared->K = geometry::SparseCholesky(K);
  const Eigen::Index n = vertex_count(), l = basis_size();
  const double s = 1.0 / (1.0 + mu_);
  Eigen::MatrixXd rhs(n, 3 + 3 * l);
  Eigen::VectorXd q = (1.0 - s) * r0_;
  for (int c = 0; c < 3; ++c) q -= s * E_[c].transpose() * g_.col(c);
  const Eigen::MatrixXd Dtg = Dt_ * g_;
  for (int c = 0; c < 3; ++c) {
    rhs.col(c) = Dtg.col(c) + U_[c] * q + anchor_rhs_.col(c);
    rhs.middleCols(3 + c * l, l) = U_[c];
  }
  const Eigen::MatrixXd solved = prepared->K.solve(rhs);
  prepared->z_constant = solved.leftCols(3);
  Eigen::MatrixXd C = (1.0 + mu_) * Eigen::MatrixXd::Identity(l, l);
  for (int c = 0; c < 3; ++c) {
    prepared->Z[c] = solved.middleCols(3 + c * l, l);
    C -= U_[c].transpose() * prepared->Z[c];
  }
  prepared->capacitance.compute(C);
  return prepared;
}

Eigen::VectorXd LearntLaplacianSpace::coefficients(const Eigen::MatrixXd& unrotated_delta) const {
  // ∂/∂r = 0: (1+μ) r = Eᵀ(δ − g) + μ r₀.
  Eigen::VectorXd r = mu_ * r0_;
  for (int c = 0; c < 3; ++c) r += E_[c].transpose() * (unrotated_delta.col(c) - g_.col(c));
  return r / (1.0 + mu_);
}

Eigen::MatrixXd LearntLaplacianSpace::estimate_rotated_target(const Eigen::MatrixXd& x, const Eigen::VectorXd& r,
                                                              std::vector<Eigen::Matrix3d>& rotations) const {
  // The shape whose differential coordinates are g + E r, up to translation.
  Eigen::MatrixXd y = reference_;
  Eigen::MatrixXd delta = g_;
  if (basis_size() > 0) {
    const Eigen::VectorXd dr = r - r0_;
    for (int c = 0; c < 3; ++c) {
      y.col(c) += shape_basis_[c] * dr;
      delta.col(c) += E_[c] * r;
    }
  }
  rotations.resize(static_cast<std::size_t>(x.rows()));
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    // Best rotation of the one-ring edges y → x (tejera2013 §III, iterative rotation update).
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    for (int j : adjacency_[i]) S += (y.row(j) - y.row(i)).transpose() * (x.row(j) - x.row(i));
    const Eigen::Matrix3d R = best_rotation(S);
    rotations[i] = R;
    delta.row(i) = (R * delta.row(i).transpose()).transpose();
  }
  return delta;
}

Eigen::MatrixXd LearntLaplacianSpace::solve(const Prepared& prepared, const Eigen::MatrixXd& targets,
                                            int rotation_iterations) const {
  const Eigen::Index n = vertex_count(), l = basis_size();
  if (targets.rows() != static_cast<Eigen::Index>(prepared.vertices.size()) || targets.cols() != 3)
    throw core::internal_error("LearntLaplacianSpace::solve: targets do not match the prepared constraints");
  Eigen::MatrixXd constraint_rhs = Eigen::MatrixXd::Zero(n, 3);
  for (std::size_t i = 0; i < prepared.vertices.size(); ++i) {
    const double w = prepared.weights[static_cast<Eigen::Index>(i)];
    constraint_rhs.row(prepared.vertices[i]) += w * w * targets.row(static_cast<Eigen::Index>(i));
  }
  // Joint solve for x and r with R = I (eq. 7), Woodbury on the low-rank part.
  Eigen::MatrixXd x = prepared.z_constant + prepared.K.solve(constraint_rhs);
  if (l > 0) {
    Eigen::VectorXd Utz = Eigen::VectorXd::Zero(l);
    for (int c = 0; c < 3; ++c) Utz += U_[c].transpose() * x.col(c);
    const Eigen::VectorXd y = prepared.capacitance.solve(Utz);
    for (int c = 0; c < 3; ++c) x.col(c) += prepared.Z[c] * y;
  }
  if (adjacency_.empty()) return x;
  Eigen::VectorXd r = l > 0 ? coefficients(D_ * x) : Eigen::VectorXd();
  std::vector<Eigen::Matrix3d> rotations;
  for (int iteration = 0; iteration < rotation_iterations; ++iteration) {
    const Eigen::MatrixXd target = estimate_rotated_target(x, r, rotations);
    x = prepared.K.solve(Dt_ * target + constraint_rhs + anchor_rhs_);
    if (l > 0) {
      Eigen::MatrixXd unrotated = D_ * x;
      for (Eigen::Index i = 0; i < n; ++i)
        unrotated.row(i) = (rotations[i].transpose() * unrotated.row(i).transpose()).transpose();
      r = coefficients(unrotated);
    }
  }
  return x;
}

}  // namespace surfcap::learn
