#pragma once
// A prefactored sparse symmetric positive-definite solver: factor once, solve many right-hand
// sides. CHOLMOD (supernodal Cholesky) when available, Eigen::SimplicialLDLT otherwise.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

namespace surfcap::geometry {

class SparseCholesky {
 public:
  enum class Backend { automatic, cholmod, simplicial_ldlt };

  SparseCholesky();
  /// Factors A (n×n, symmetric positive definite; the lower triangle is read). Throws
  /// core::internal_error when A is not positive definite.
  explicit SparseCholesky(const Eigen::SparseMatrix<double>& A, Backend backend = Backend::automatic);
  ~SparseCholesky();
  /// Factors A again, reusing the ordering and symbolic analysis of the previous factorisation
  /// when A has its sparsity pattern (the same factor, bit for bit, as a fresh SparseCholesky(A)),
  /// from scratch otherwise.
  void refactor(const Eigen::SparseMatrix<double>& A);
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  /// X = A⁻¹ B for B n×k (k right-hand sides at once). Not safe to call from several threads
  /// on the same object (CHOLMOD keeps workspace).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;

  long size() const;
  bool factored() const { return impl_ != nullptr; }
  Backend backend() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surfcap::geometry
