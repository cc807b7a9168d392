#include "surfcap/geometry/sparse_cholesky.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <optional>

#include "surfcap/core/error.hpp"

namespace surfcap::geometry {

struct SparseCholesky::Impl {
  long n = 0;
  Backend backend = Backend::cholmod;
  std::optional<Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>> cholmod;
  std::optional<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>> ldlt;
};

SparseCholesky::SparseCholesky() = default;
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

SparseCholesky::SparseCholesky(const Eigen::SparseMatrix<double>& A, Backend backend)
    : impl_(std::make_unique<Impl>()) {
  if (A.rows() != A.cols()) throw core::internal_error("SparseCholesky: matrix is not square");
  impl_->n = A.rows();
  if (backend != Backend::simplicial_ldlt) {
    impl_->cholmod.emplace();
    // LLᵀ (not CHOLMOD's automatic LDLᵀ for small matrices), so an indefinite matrix fails.
    impl_->cholmod->setMode(Eigen::CholmodSupernodalLLt);
    impl_->cholmod->compute(A);
    if (impl_->cholmod->info() == Eigen::Success) {
      impl_->backend = Backend::cholmod;
      return;
    }
    impl_->cholmod.reset();
    if (backend == Backend::cholmod)
      throw core::internal_error("SparseCholesky: CHOLMOD factorisation failed (matrix not positive definite?)");
  }
  impl_->ldlt.emplace(A);
  impl_->backend = Backend::simplicial_ldlt;
  if (impl_->ldlt->info() != Eigen::Success || (impl_->ldlt->vectorD().array() <= 0).any())
    throw core::internal_error("SparseCholesky: factorisation failed (matrix not positive definite)");
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
  if (!impl_) throw core::internal_error("SparseCholesky::solve before factorisation");
  if (B.rows() != impl_->n) throw core::internal_error("SparseCholesky::solve: right-hand side has wrong size");
  if (B.cols() == 0) return B;
  if (impl_->cholmod) return impl_->cholmod->solve(B);
  return impl_->ldlt->solve(B);
}

long SparseCholesky::size() const { return impl_ ? impl_->n : 0; }
SparseCholesky::Backend SparseCholesky::backend() const {
  return impl_ ? impl_->backend : Backend::automatic;
}

}  // namespace surfcap::geometry
