#pragma once
// The constrained least-squares problem of one part (tejera2013 eq. 7), prefactored:
//   min_{x,r} ‖D x − R(g + E r)‖² + ‖W(S x − c)‖² + μ‖r − r₀‖²
// D: Laplacian operator (m×n), E: learnt basis, g: mean (plus the reference pose's detail),
// R: per-vertex rotations updated iteratively (R = I in the first, joint, solve).
// The joint solve eliminates r: (K − s U Uᵀ) x = b with K = DᵀD + SᵀW²S (sparse, factored once
// per handle set), U = DᵀE, s = 1/(1+μ), solved by the Woodbury identity so an edit costs one
// sparse solve with 3 right-hand sides plus O(n·l).
#include <Eigen/Core>
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <vector>

#include "surfcap/geometry/sparse_cholesky.hpp"

namespace surfcap::learn {

class LearntLaplacianSpace {
 public:
  /// D m×n; basis[c] m×l (coordinate c rows of E); g m×3; r0 l; reference n×3 (the pose the
  /// rotations are measured from). rotation_adjacency (size n, empty to disable rotation
  /// updates; then m need not equal n).
  LearntLaplacianSpace(Eigen::SparseMatrix<double> D, std::array<Eigen::MatrixXd, 3> basis, Eigen::MatrixXd g,
                       Eigen::VectorXd r0, Eigen::MatrixXd reference, double regularisation,
                       std::vector<std::vector<int>> rotation_adjacency);

  /// The factorisations for one set of constrained vertices (local indices) and weights.
  struct Prepared {
    std::vector<int> vertices;
    Eigen::VectorXd weights;  ///< w (the energy has w²)
    geometry::SparseCholesky K;
    std::array<Eigen::MatrixXd, 3> Z;  ///< K⁻¹ U_c
    Eigen::LLT<Eigen::MatrixXd> capacitance;
    Eigen::MatrixXd z_constant;  ///< K⁻¹ (Dᵀ g + U q), n×3
  };
  std::unique_ptr<Prepared> prepare(const std::vector<int>& vertices, const Eigen::VectorXd& weights) const;

  /// Positions (n×3) for constraint targets (k×3, rows matching prepared.vertices).
  Eigen::MatrixXd solve(const Prepared& prepared, const Eigen::MatrixXd& targets, int rotation_iterations) const;

  long vertex_count() const { return reference_.rows(); }
  long basis_size() const { return r0_.size(); }

 private:
  Eigen::VectorXd coefficients(const Eigen::MatrixXd& unrotated_delta) const;
  Eigen::MatrixXd estimate_rotated_target(const Eigen::MatrixXd& x, const Eigen::VectorXd& r,
                                          std::vector<Eigen::Matrix3d>& rotations) const;

  Eigen::SparseMatrix<double> D_, Dt_;
  Eigen::SparseMatrix<double> DtD_;
  std::array<Eigen::MatrixXd, 3> E_, U_, shape_basis_;
  Eigen::MatrixXd g_, reference_, anchor_rhs_;
  double tikhonov_ = 0;
  Eigen::VectorXd r0_;
  double mu_;
  std::vector<std::vector<int>> adjacency_;
};

}  // namespace surfcap::learn
